"""b-bit pulse-width resolution: the quantiser of the slot counts and the slot layout.

Both follow ``docs/contract.md`` (section "b-bit pulse-width resolution: the
gating-signal generator") and :mod:`mdfqm_model.bbit`; :class:`mdfqm_model.clock.GeneratorModel`
predicts every bit of them on every clock, through :class:`GatingSignalGenerator`.
"""

from amaranth import Array, Cat, Const, Module, Mux, Shape, Signal, signed, unsigned
from amaranth.lib import data, wiring
from amaranth.lib.wiring import In, Out

from mdfqm_spec.contract import (
    BITS_WIDTH,
    MAX_BITS_LIMIT,
    MODE_WIDTH,
    MODES,
    Contract,
    ceil_log2,
    signed_bits,
    validate_max_bits,
)
from mdfqm_spec.validate import validate_positive

from .arith import at_least

__all__ = ["Quantiser", "SlotLayout"]

SVPWM, DPWM0, DPWM = (MODES.index(name) for name in ("svpwm", "dpwm0", "dpwm"))


def _lookup(values, index, shape):
    """``values[index]`` as a table of constants (indices past the end read the last entry)."""
    padded = list(values) + [values[-1]] * ((1 << len(index)) - len(values))
    return Array(Const(v, shape) for v in padded)[index]


def _table(m, values, index, shape, name):
    """A registered lookup ``values[index]`` (``index`` changes only at update starts). Only
    the bits that differ between the values are registered; a bit all of them share is a
    constant, so that no flop holds a bit that can never change."""
    shape = Shape.cast(shape)
    varying = [k for k in range(shape.width) if len({(v >> k) & 1 for v in values}) > 1]
    held = Signal(len(varying), name=name)
    m.d.sync += held.eq(_lookup([sum(((v >> k) & 1) << j for j, k in enumerate(varying))
                                 for v in values], index, unsigned(len(varying))))
    bits = [held[varying.index(k)] if k in varying else Const((values[0] >> k) & 1, 1)
            for k in range(shape.width)]
    return Cat(*bits).as_signed() if shape.signed else Cat(*bits)


class Quantiser(wiring.Component):
    """Slot counts of one gamma-mode update, their mean feedback and the centred layout bounds.

    Arithmetic (contract, "b-bit pulse-width resolution"; ``NF = N FULL``, ``B = max_bits``,
    ``S = 2**b``), all legs in parallel, every stage at most one carry chain:

    1. ``max(T) + min(T)`` (the sector of the dpwm clamp) and the per-update offsets of
       ``g2 = 2 gamma`` = 0 and 2: ``g2 NF + (2 - g2) max + g2 min + NF / S``;
    2. that of ``g2 = 1``, then the selection of the mode's ``g2`` (for dpwm by the sign of
       ``max + min``);
    3. per leg ``V_i = offset - 2 T_i`` (= ``2 C_i + NF / S``, the leg's rounded switching
       instant); then, with the load of the divider, ``V_i >= 2 NF`` (the top quotient bit:
       a compare with a constant, logic on the register's bits) and the clamp to
       ``[0, 2 NF]``;
    4. ``B`` clocks of restoring division by the constant ``2 NF`` (one quotient bit a clock;
       after ``b`` bits the rest are forced to 0): ``m_i = q_i 2**(B - b)``; of ``V_i`` and
       ``2 NF`` both shifted right by the bits below every boundary ``j 2 NF / 2**B`` (which
       no quotient depends on);
    5. alongside the division, one clock behind it, the feedback
       ``U_i / (FULL / 2**B) = sum_k m_k - N m_i``, most significant quotient bit first
       (doubled, plus the bits of the step: no sums over the legs after the division);
    6. the layout bounds ``lo_i = floor(q_i / 2) 2**(B - b)``, ``hi_i = lo_i + (2**B - m_i)``
       (one adder); the outputs are presented ``ceil(log2 N) + 1`` clocks after the
       division's last quotient bit (the latency the contract fixes: the feedback and the
       bounds are final before, and hold until the next load).

    Slot indices are scaled to ``2**B`` (slot ``j`` is ``j 2**(B - b)``), so no shift by the
    runtime ``b`` is needed anywhere but in small registered tables.

    Ports
    -----
    i_t : In(ArrayLayout(signed(t_width), phases))
        ``T`` of the update (the integrators' output; still from the start to the result).
    i_max, i_min : In(signed(t_width))
        ``max(T)`` and ``min(T)`` (sort1's first and last output).
    i_valid : In(1)
        Strobe: ``i_max``/``i_min`` are this update's (sort1's valid).
    i_mode : In(MODE_WIDTH)
        Mode code of the update (latched; still through the update).
    i_bits : In(BITS_WIDTH)
        b of the update, in ``[1, max_bits]`` for a gamma mode (latched; still).
    o_units_n : Out(ArrayLayout(signed(units_width), phases))
        ``~(sum_k m_k - N m_i)``: the feedback in units of ``FULL / 2**B``, given inverted (as
        the integrators take it); valid with ``o_valid``.
    o_lo, o_hi : Out(ArrayLayout(unsigned(max_bits + 1), phases))
        Leg i is on in the slots with scaled index ``lo_i <= j < hi_i``; valid with ``o_valid``.
    o_first : Out(phases)
        State of the first slot (``lo_i == 0``); valid with ``o_valid``.
    o_last : Out(phases)
        State of the last slot (``q_i == 0``); valid with ``o_valid``.
    o_slots : Out(max_bits)
        ``S - 1`` (registered table of ``i_bits``).
    o_delta : Out(max_bits + 1)
        ``2**(B - b)``: one slot in scaled units (registered table of ``i_bits``).
    o_valid : Out(1)
        ``i_valid`` delayed by ``latency`` clocks.

    Parameters
    ----------
    phases, width : int
        As the core's.
    max_bits : int in [1, min(12, width - 2)]
        B, the largest resolution.

    Attributes
    ----------
    latency : int
        ``5 + max_bits + ceil(log2 phases)`` clocks from ``i_valid`` to ``o_valid``.
    """

    def __init__(self, phases: int, width: int, max_bits: int):
        self.contract = Contract(phases, width)
        self.max_bits = validate_max_bits(max_bits, width)
        self.phases, self.width = phases, width
        units_max = (phases - 1) << max_bits
        self.units_width = signed_bits(-units_max, units_max)
        c = self.contract
        index = unsigned(max_bits + 1)
        super().__init__({
            "i_t": In(data.ArrayLayout(signed(c.t_width), phases)),
            "i_max": In(signed(c.t_width)),
            "i_min": In(signed(c.t_width)),
            "i_valid": In(1),
            "i_mode": In(MODE_WIDTH),
            "i_bits": In(BITS_WIDTH),
            "o_units_n": Out(data.ArrayLayout(signed(self.units_width), phases)),
            "o_lo": Out(data.ArrayLayout(index, phases)),
            "o_hi": Out(data.ArrayLayout(index, phases)),
            "o_first": Out(phases),
            "o_last": Out(phases),
            "o_slots": Out(max_bits),
            "o_delta": Out(max_bits + 1),
            "o_valid": Out(1),
        })

    @property
    def latency(self) -> int:
        return 5 + self.max_bits + ceil_log2(self.phases)

    def elaborate(self, platform):
        m = Module()
        n, c, bmax = self.phases, self.contract, self.max_bits
        nf = c.unit
        div = 2 * nf
        b_range = range(bmax + 1)

        # ---- per-update constants of b (registered lookups; b is still through the update)
        wide = signed(c.t_width + 3)
        k_tab = [_table(m, [g * nf + (nf >> b) for b in b_range], self.i_bits, wide, f"k{g}")
                 for g in range(3)]
        lo_mask = _table(m, [((1 << (bmax + 1)) - 1) & ~((1 << (bmax - b)) - 1) for b in b_range],
                         self.i_bits, unsigned(bmax + 1), "lo_mask")
        m.d.sync += [
            self.o_slots.eq(_lookup([(1 << b) - 1 for b in b_range], self.i_bits,
                                    unsigned(bmax))),
            self.o_delta.eq(_lookup([1 << (bmax - b) for b in b_range], self.i_bits,
                                    unsigned(bmax + 1))),
        ]

        # ---- stage 1: the sector sum, and the dpwm offsets (one adder each, in parallel)
        sum_mm = Signal(signed(c.t_width + 1))
        ofs = {name: Signal(wide, name=name) for name in ("o0", "o2")}
        m.d.sync += [
            sum_mm.eq(self.i_max + self.i_min),
            ofs["o0"].eq(self.i_max * 2 + k_tab[0]),
            ofs["o2"].eq(self.i_min * 2 + k_tab[2]),
        ]
        # the mode decoded once (it is still through the update)
        is_svpwm, is_dpwm0, is_dpwm = Signal(), Signal(), Signal()
        m.d.sync += [is_svpwm.eq(self.i_mode == SVPWM), is_dpwm0.eq(self.i_mode == DPWM0),
                     is_dpwm.eq(self.i_mode == DPWM)]

        # ---- stage 2: the svpwm offset, then the zero split selects (after the adders)
        g_zero = is_dpwm0 | (is_dpwm & ~sum_mm[-1])
        # held inverted: ``V_i = ~(2 T_i + ~offset)`` is then an addition of the registers as
        # they are (a subtraction would put an inverter in front of every bit of its carry
        # chain); the inversion of its sum is free in the sum's own logic
        offset_n = Signal(wide)
        m.d.sync += offset_n.eq(~Mux(is_svpwm, sum_mm + k_tab[1],
                                     Mux(g_zero, ofs["o0"], ofs["o2"])))

        # ---- stage 3: per-leg instants; stage 4: clamped, loaded into the divider
        valid = [self.i_valid]
        for k in range(self.latency):
            reg = Signal(name=f"valid{k + 1}")
            m.d.sync += reg.eq(valid[-1])
            valid.append(reg)
        load = valid[3]
        # every decision boundary j 2 NF / 2**b (b <= B) is a multiple of 2**low, so no quotient
        # depends on the low bits of V: the divider works on V >> low by 2 NF >> low
        low = ((div & -div).bit_length() - 1) - bmax
        div_low = div >> low
        rem_shape = unsigned(div_low.bit_length())
        run = Signal(range(bmax + 1))
        want = Signal(range(bmax + 1))
        with m.If(load):
            m.d.sync += [run.eq(bmax), want.eq(self.i_bits)]
        with m.Elif(run != 0):
            m.d.sync += [run.eq(run - 1), want.eq(Mux(want != 0, want - 1, 0))]
        quotients = []
        for i in range(n):
            t2 = self.i_t[i] * 2
            v = Signal(wide, name=f"v{i}")
            m.d.sync += v.eq(~(t2 + offset_n))
            # V >= 2 NF: the top quotient bit (a compare of a register with a constant, logic on
            # its bits, no carry chain)
            beyond = ~v[-1] & at_least(v[:-1], div)
            top = Signal(name=f"top{i}")
            rem = Signal(rem_shape, name=f"rem{i}")
            q = Signal(bmax, name=f"q{i}")
            # ---- stage 5: B restoring steps, 2 rem - 2NF, one carry chain a clock
            trial = Signal(signed(rem_shape.width + 2), name=f"trial{i}")
            m.d.comb += trial.eq((rem << 1) - div_low)
            fits = ~trial[-1]
            with m.If(load):
                m.d.sync += [
                    top.eq(beyond),
                    rem.eq(Mux(v[-1] | beyond, 0, v[low:])),
                ]
            with m.Elif(run != 0):
                # the B shifts push out every bit q held before the load
                m.d.sync += [
                    rem.eq(Mux(fits, trial, rem << 1)),
                    q.eq(Cat(fits & (want != 0), q[:-1]) if bmax > 1 else fits & (want != 0)),
                ]
            quotients.append(Cat(q, top))

        # ---- the feedback, accumulated one clock behind the division, most significant
        # quotient bit first: U_i = sum_k m_k - N m_i, doubled and added to at each step from
        # the bits the step registered (no sums over the legs after the division, and no
        # carry chain behind the divider's in one clock). It is final ``ceil(log2 N)``
        # clocks before o_valid and holds until the next load. Held inverted, as the
        # integrators take it: ``~(2 U + s) = (2 ~U + 1) - s``, the step's negation shared.
        loaded = valid[4]                  # the clock after the load
        stepped = Signal(name="stepped")   # the clock after a division step
        m.d.sync += stepped.eq(~load & (run != 0))
        # the count of set bits among the legs, and that count minus N (each negated for the
        # steps), shared by the legs: a leg selects one (a multiplexer, so that its update is
        # one adder)
        step_shape = signed(signed_bits(-n, n))
        tops, newest = [q[-1] for q in quotients], [q[0] for q in quotients]
        tops_set, tops_set_minus_n = Signal(step_shape), Signal(step_shape)
        newest_neg, newest_n_minus = Signal(step_shape), Signal(step_shape)
        m.d.comb += [tops_set.eq(sum(tops)), tops_set_minus_n.eq(tops_set - n),
                     newest_neg.eq(-sum(newest)), newest_n_minus.eq(newest_neg + n)]
        for i in range(n):
            units_n = Signal(signed(self.units_width), name=f"units_n{i}")
            step_neg = Signal(step_shape, name=f"units_step_neg{i}")
            m.d.comb += step_neg.eq(Mux(newest[i], newest_n_minus, newest_neg))
            with m.If(loaded):
                m.d.sync += units_n.eq(~Mux(tops[i], tops_set_minus_n, tops_set))
            with m.Elif(stepped):
                m.d.sync += units_n.eq(Cat(Const(1, 1), units_n).as_signed() + step_neg)
            m.d.comb += self.o_units_n[i].eq(units_n)
        # ---- the layout bounds, from the final quotient: lo_i = floor(q_i / 2) (its bit
        # below one slot cleared), hi_i = lo_i + 2**B - q_i
        for i in range(n):
            lo = Signal(unsigned(bmax + 1), name=f"lo{i}")
            hi = Signal(unsigned(bmax + 1), name=f"hi{i}")
            last = Signal(name=f"last{i}")
            m.d.comb += lo.eq((quotients[i] >> 1) & lo_mask)
            m.d.sync += [
                hi.eq(lo - quotients[i] + (1 << bmax)),
                last.eq(quotients[i] == 0),
            ]
            m.d.comb += [
                self.o_lo[i].eq(lo),
                self.o_hi[i].eq(hi),
                self.o_first[i].eq(lo == 0),
                self.o_last[i].eq(last),
            ]
        m.d.comb += self.o_valid.eq(valid[-1])
        return m


class SlotLayout(wiring.Component):
    """The gate state: an MDFQM state held, or a slot layout played out clock by clock.

    At ``i_load`` (registered: the new output is visible in the next cycle) it takes either the
    constant state ``i_h`` (``i_bbit = 0``) or a layout: slots of ``i_slot_m2 + 2`` clocks,
    ``i_slots + 1`` of them, the last one held until the next load; leg i on in the slots with
    scaled index ``i_lo[i] <= j < i_hi[i]`` (``j`` advances by ``i_delta``). The state changes
    only at loads and slot boundaries: at a boundary into slot ``j`` a leg turns off if
    ``j == hi``, else on if ``j == lo`` (equality of registers, no comparator chain). A slot ends
    when a signed count-down turns negative (its sign bit, no zero detect), and whether another
    slot follows is a registered flag.

    Ports
    -----
    i_load : In(1)
        Load the next update's output (an update's presentation is the next cycle).
    i_bbit : In(1)
        With ``i_load``: 1 a layout, 0 the constant state ``i_h``.
    i_h : In(phases)
        The MDFQM state.
    i_first : In(phases)
        State of the layout's first slot.
    i_lo, i_hi : In(ArrayLayout(unsigned(max_bits + 1), phases))
        Layout bounds in scaled slot indices.
    i_slots : In(max_bits)
        Number of slots after the first (``S - 1``).
    i_delta : In(max_bits + 1)
        One slot in scaled indices.
    i_slot_m2 : In(signed(period_width))
        Clocks per slot minus two (>= -1): a slot is at most half of a ``period_width``-bit
        period (``b >= 1``), so the count fits ``period_width`` signed bits.
    o_h : Out(phases)
        Gate state (registered; 0 after reset).

    Parameters
    ----------
    phases : int >= 3
    max_bits : int in [1, MAX_BITS_LIMIT]
    period_width : int in [2, 32]
    """

    def __init__(self, phases: int, max_bits: int, period_width: int = 16):
        validate_positive(phases, "phases", minimum=3)
        validate_positive(max_bits, "max_bits", minimum=1, maximum=MAX_BITS_LIMIT)
        validate_positive(period_width, "period_width", minimum=2, maximum=32)
        self.phases, self.max_bits, self.period_width = phases, max_bits, period_width
        index = unsigned(max_bits + 1)
        super().__init__({
            "i_load": In(1),
            "i_bbit": In(1),
            "i_h": In(phases),
            "i_first": In(phases),
            "i_lo": In(data.ArrayLayout(index, phases)),
            "i_hi": In(data.ArrayLayout(index, phases)),
            "i_slots": In(max_bits),
            "i_delta": In(max_bits + 1),
            "i_slot_m2": In(signed(period_width)),
            "o_h": Out(phases),
        })

    def elaborate(self, platform):
        m = Module()
        n, bmax = self.phases, self.max_bits
        lo = [Signal(bmax + 1, name=f"lo{i}") for i in range(n)]
        hi = [Signal(bmax + 1, name=f"hi{i}") for i in range(n)]
        # the leg toggles at the next slot boundary are registers, compared one slot ahead
        # against the index of the slot after it (so a 1-clock slot needs no compare in front
        # of the gates)
        turn_on = [Signal(name=f"turn_on{i}") for i in range(n)]
        turn_off = [Signal(name=f"turn_off{i}") for i in range(n)]
        after = Signal(bmax + 2)         # scaled index of the slot after the next one
        delta = Signal(bmax + 1)
        left = Signal(bmax)              # slots still to begin
        more = Signal()                  # left != 0
        count = Signal(signed(self.period_width))   # clocks left in this slot, minus two
        slot_m2 = Signal(signed(self.period_width))
        advance = count[-1] & more
        with m.If(self.i_load):
            m.d.sync += [lo[i].eq(self.i_lo[i]) for i in range(n)]
            m.d.sync += [hi[i].eq(self.i_hi[i]) for i in range(n)]
            m.d.sync += [turn_off[i].eq(self.i_delta == self.i_hi[i]) for i in range(n)]
            m.d.sync += [turn_on[i].eq(self.i_delta == self.i_lo[i]) for i in range(n)]
            m.d.sync += [
                self.o_h.eq(Mux(self.i_bbit, self.i_first, self.i_h)),
                after.eq(self.i_delta * 2),
                delta.eq(self.i_delta),
                left.eq(self.i_slots),
                more.eq(self.i_bbit & (self.i_slots != 0)),
                count.eq(self.i_slot_m2),
                slot_m2.eq(self.i_slot_m2),
            ]
        with m.Elif(advance):
            m.d.sync += [turn_off[i].eq(after == hi[i]) for i in range(n)]
            m.d.sync += [turn_on[i].eq(after == lo[i]) for i in range(n)]
            m.d.sync += [
                after.eq(after + delta),
                left.eq(left - 1),
                more.eq(left != 1),
                count.eq(slot_m2),
                self.o_h.eq(Cat(*[Mux(turn_off[i], 0, Mux(turn_on[i], 1, self.o_h[i]))
                                  for i in range(n)])),
            ]
        with m.Elif(~count[-1]):
            m.d.sync += count.eq(count - 1)
        return m
