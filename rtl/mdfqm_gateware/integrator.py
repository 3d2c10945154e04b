"""Weighting-filter integrators: T = X + R at the update start, X <- T - v(h) at the commit."""

from amaranth import Cat, Module, Mux, ResetSignal, Signal, signed
from amaranth.hdl import Assert, Assume, Cover
from amaranth.lib import data, wiring
from amaranth.lib.wiring import In, Out

from mdfqm_spec.contract import Contract, signed_bits
from mdfqm_spec.validate import validate_bool, validate_positive

from .arith import difference

__all__ = ["Integrator"]


class Integrator(wiring.Component):
    """Per-phase integrators ``z/(z-1)`` in the exact N-scaled integer domain, with anti-windup.

    Contract (``docs/contract.md``): ``T = X + R`` is registered at the update start and
    held for the whole update (the pipeline behind it reads it until the commit). At the commit
    ``U_i = FULL (N h_i - k)`` and ``X' = T - U``; if any ``X'_i`` leaves the signed
    ``x_width``-bit range the integrators keep their value and ``o_saturated`` is set (conditional
    integration: ``sum(X) == 0`` holds exactly and nothing can wrap).

    Ports
    -----
    i_start : In(1)
        Update start: load ``T``.
    i_r : In(ArrayLayout(signed(r_width), phases))
        Reference used by the update starting this cycle.
    i_commit : In(1)
        Commit cycle: ``i_h``/``i_count`` hold this update's state.
    i_units_n : In(ArrayLayout(signed(units_width), phases))
        Feedback of this update in units of ``2**unit_shift``, given inverted:
        ``~(U_i / 2**unit_shift)`` (for the core ``unit_shift = width - 2``, so ``U_i /
        2**unit_shift`` is ``N h_i - k``), valid with ``i_commit``; ``|U_i| <= (N - 1) FULL``.
        ``T - U`` is then ``T + ~U + 1``, an addition of the value as given (on the iCE40 an
        inverter in front of a carry chain is a LUT a bit).
    o_t : Out(ArrayLayout(signed(t_width), phases))
        Optimum signal of the current update (registered, valid from the cycle after a start).
    o_x : Out(ArrayLayout(signed(x_width), phases))
        Integrator state (registered; a saturated commit leaves it as it was).
    o_saturated : Out(1)
        Registered at each commit: that update was held by the bound.

    Parameters
    ----------
    phases, width : int
        As the core's.
    unit_shift : int in [0, width - 2] or None
        The feedback comes in units of ``2**unit_shift`` (None: ``width - 2``, i.e. ``FULL``,
        the core's). The generator uses ``width - 2 - max_bits``: the commit adds only the bits
        from ``unit_shift`` up.
    kept_copy : bool
        False: one register a phase, written at a commit only if every phase fits (the bound
        check steers its enables). True: the commit writes the new value unconditionally and
        keeps a copy of the one it replaces, and ``o_saturated`` selects which one is the
        integrator, so the bound check ends at one flip-flop (a register and a multiplexer
        a bit more: for the generator, whose feedback comes wide and through its mode select,
        the path that sets its Fmax). The same values at the ports either way.
    """

    def __init__(self, phases: int, width: int, unit_shift: int | None = None,
                 formal: bool = False, formal_sums: bool = True, kept_copy: bool = False):
        self.contract = Contract(phases, width)
        self.formal = validate_bool(formal, "formal")
        self.kept_copy = validate_bool(kept_copy, "kept_copy")
        self.formal_sums = validate_bool(formal_sums, "formal_sums")
        self.phases = phases
        c = self.contract
        if unit_shift is None:
            unit_shift = width - 2
        validate_positive(unit_shift, "unit_shift", minimum=0, maximum=width - 2)
        self.unit_shift = unit_shift
        units_max = (phases - 1) << (width - 2 - unit_shift)
        self.units_width = signed_bits(-units_max, units_max)
        super().__init__({
            "i_start": In(1),
            "i_r": In(data.ArrayLayout(signed(c.r_width), phases)),
            "i_commit": In(1),
            "i_units_n": In(data.ArrayLayout(signed(self.units_width), phases)),
            "o_t": Out(data.ArrayLayout(signed(c.t_width), phases)),
            "o_x": Out(data.ArrayLayout(signed(c.x_width), phases)),
            "o_saturated": Out(1),
        })

    def elaborate(self, platform):
        m = Module()
        n, c = self.phases, self.contract
        with m.If(self.i_start):
            m.d.sync += [self.o_t[i].eq(self.o_x[i] + self.i_r[i]) for i in range(n)]

        # U is a multiple of 2**shift (FULL in the core), so X' = T - U keeps T's low bits and
        # only the bits above them go through an adder. X' fits the signed x_width-bit word iff
        # its bits above the word's sign bit are all copies of it: a few LUTs instead of two
        # compare chains.
        shift = self.unit_shift
        fits_each, x_next = [], []
        for i in range(n):
            high = Signal(signed(c.t_width + 1 - shift), name=f"x_next{i}_high")
            m.d.comb += high.eq(difference(self.o_t[i][shift:].as_signed(), False,
                                           self.i_units_n[i], True))
            top = high[c.x_width - 1 - shift:]
            fits_each.append((top == 0) | (top == (1 << len(top)) - 1))
            x_next.append(Cat(self.o_t[i][:shift], high))
        fits = Signal()      # named: the formal tests' "unbounded integrator" variant forces it
        m.d.comb += fits.eq(Cat(*fits_each).all())
        # conditional integration (kept_copy: see the parameter)
        if self.kept_copy:
            x_written = Signal(data.ArrayLayout(signed(c.x_width), n))
            x_kept = Signal(data.ArrayLayout(signed(c.x_width), n))
            m.d.comb += self.o_x.eq(Mux(self.o_saturated, x_kept, x_written))
            with m.If(self.i_commit):
                m.d.sync += [x_written[i].eq(x_next[i]) for i in range(n)]
                m.d.sync += x_kept.eq(self.o_x)
            registers = (x_written, x_kept)
        else:
            x = Signal(data.ArrayLayout(signed(c.x_width), n))
            m.d.comb += self.o_x.eq(x)
            with m.If(self.i_commit & fits):
                m.d.sync += [x[i].eq(x_next[i]) for i in range(n)]
            registers = None
        with m.If(self.i_commit):
            m.d.sync += self.o_saturated.eq(~fits)
        if self.formal:
            self._properties(m, registers)
        return m

    def _properties(self, m, registers):
        """Contract property 5, per phase: the integrators never wrap, for any reference and any
        feedback the ports can carry (no assumption: this also holds inside the core). After a start
        ``T = X + R`` exactly; after a commit ``X = T - U`` exactly, or every phase held and
        ``o_saturated`` set."""
        n, c = self.phases, self.contract
        exact_width = c.t_width + 2
        # what this cycle's start and commit must produce, one clock later
        start_prev = Signal(reset_less=True)
        commit_prev = Signal(reset_less=True)
        rst_prev = Signal(reset_less=True)
        t_exact_prev = Signal(data.ArrayLayout(signed(exact_width), n), reset_less=True)
        x_exact_prev = Signal(data.ArrayLayout(signed(exact_width), n), reset_less=True)
        x_prev = Signal(data.ArrayLayout(signed(c.x_width), n), reset_less=True)
        m.d.sync += [start_prev.eq(self.i_start), commit_prev.eq(self.i_commit),
                     rst_prev.eq(ResetSignal()), x_prev.eq(self.o_x)]
        m.d.sync += [t_exact_prev[i].eq(self.o_x[i] + self.i_r[i]) for i in range(n)]
        m.d.sync += [x_exact_prev[i].eq(self.o_t[i] - (~self.i_units_n[i] << self.unit_shift))
                     for i in range(n)]
        after_start = start_prev & ~rst_prev
        after_commit = commit_prev & ~rst_prev
        for i in range(n):
            m.d.comb += [
                Assert(~after_start | (self.o_t[i] == t_exact_prev[i]),
                       "T differs from X + R after a start (it wrapped)"),
                Assert(~after_commit | self.o_saturated | (self.o_x[i] == x_exact_prev[i]),
                       "integrator differs from T - U after a commit (it wrapped)"),
                Assert(~after_commit | ~self.o_saturated | (self.o_x[i] == x_prev[i]),
                       "integrator not held by a saturated commit"),
            ]
        m.d.comb += Cover(after_commit & self.o_saturated)
        if self.formal_sums:
            self._sum_properties(m, registers)

    def _sum_properties(self, m, registers):
        """``sum(X) == 0`` for any reference and feedback sequences that each sum to zero (as
        the reference stage and the decoder guarantee). It follows from the per-phase
        exactness by linearity; proving it again costs the solver an adder-tree rearrangement
        that grows quickly with ``N``."""
        n = self.phases
        m.d.comb += [
            Assume(sum(self.i_r[i] for i in range(n)) == 0),
            Assume(sum(~self.i_units_n[i] for i in range(n)) == 0),
        ]

        def total(value):
            return sum(value[i] for i in range(n))

        m.d.comb += [
            Assert(total(self.o_x) == 0, "integrator state does not sum to zero"),
            # inductive helpers: what the registers behind T and o_x hold
            Assert(total(self.o_t) == 0, "T does not sum to zero"),
        ]
        if registers is not None:
            x_written, x_kept = registers
            m.d.comb += [
                Assert(total(x_kept) == 0, "the kept integrator state does not sum to zero"),
                Assert(self.o_saturated | (total(x_written) == 0),
                       "the written integrator state does not sum to zero"),
            ]
