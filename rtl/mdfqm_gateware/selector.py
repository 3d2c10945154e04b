"""Selection: duties or exact scores of the staircase states, sort2 (the max-tournament), and
the decoder that turns the winner back into the gate state h."""

from amaranth import Array, Cat, Const, Module, Mux, ResetSignal, Signal, signed
from amaranth.hdl import Assert, Assume, Cover
from amaranth.lib import data, wiring
from amaranth.lib.wiring import In, Out

from mdfqm_spec.contract import ARGMAX_GROUP, Contract, argmax_stages, signed_bits, validate_rule
from mdfqm_spec.validate import validate_bool, validate_positive

from .arith import as_held, at_least_given, difference
from .properties import delayed, is_permutation

__all__ = ["ArgMax", "Candidates", "StateDecoder", "candidate_width", "rho_held_inverted",
           "values_held_inverted"]


def candidate_width(phases: int, width: int) -> int:
    """Width of a duty or score: both are bounded by ``2 N max|T|`` plus the constant term."""
    c = Contract(phases, width)
    t_max = 1 << (c.t_width - 1)
    bound = 2 * phases * t_max + c.full * phases * phases
    return signed_bits(-bound, bound)


def rho_held_inverted(phases: int, rule: str) -> frozenset[int]:
    """The positions of sort1's output the candidates take inverted (``~rho_j``).

    A subtraction needs one operand inverted, and on the iCE40 an inverter in front of a carry
    chain is a LUT a bit, while sort1 gives any output inverted at no cost. The duties
    ``rho_{j-1} - rho_j`` take every other ``rho`` inverted (the odd positions); the first and
    the last are never inverted (the b-bit quantiser takes them as they are, and ``d_0`` is an
    addition of them). The exact scores add the ``rho``: none inverted."""
    if rule != "largest_duty":
        return frozenset()
    return frozenset(range(1, phases - 1, 2))


def values_held_inverted(count: int) -> frozenset[int]:
    """The candidates given inverted to sort2 (``~value``): the odd positions of each group
    of ``ARGMAX_GROUP``. sort2 compares every pair of a group; a compare of one value given
    inverted and one not is an addition of the two as given (``arith.at_least_given``), and
    the candidates are sums, which give their value inverted at no cost."""
    return frozenset(i for i in range(count) if i % ARGMAX_GROUP % 2 == 1)


class Candidates(wiring.Component):
    """Values of the N staircase candidates ``j = 0..N-1`` (``j = 0`` the zero class), one clock.

    ``rule = "largest_duty"``: ``d_0 = N FULL - (rho_1 - rho_N)``, ``d_j = rho_j - rho_{j+1}``
    (the patent's duties with both zero states combined, gamma = 1).
    ``rule = "exact_nearest"``: ``S_j = 2 (rho_1 + ... + rho_j) - FULL j (N - j)``, ``S_0 = 0``.

    Ports
    -----
    i_rho : In(ArrayLayout(signed(t_width), phases))
        Sorted optimum signal (sort1's output), largest first; ``i_rho[j]`` is ``~rho_j`` (the
        value inverted) for ``j`` in ``rho_inverted``.
    i_valid : In(1)
    o_values : Out(ArrayLayout(signed(candidate_width), phases))
        Candidate values of ``i_rho`` one clock earlier; ``o_values[j]`` is the value inverted
        (``~value``) for ``j`` in :func:`values_held_inverted` (as sort2 takes them). 0 after a
        reset (as given).
    o_valid : Out(1)
        ``i_valid`` one clock earlier.
    """

    def __init__(self, phases: int, width: int, rule: str = "largest_duty"):
        self.contract = Contract(phases, width)
        self.rule = validate_rule(rule, phases)
        self.phases, self.width = phases, width
        self.value_width = candidate_width(phases, width)
        self.rho_inverted = rho_held_inverted(phases, self.rule)
        super().__init__({
            "i_rho": In(data.ArrayLayout(signed(self.contract.t_width), phases)),
            "i_valid": In(1),
            "o_values": Out(data.ArrayLayout(signed(self.value_width), phases)),
            "o_valid": Out(1),
        })

    latency = 1

    def elaborate(self, platform):
        m = Module()
        n, c = self.phases, self.contract
        rho = [self.i_rho[i] for i in range(n)]
        inverted = [j in self.rho_inverted for j in range(n)]
        if self.rule == "largest_duty":
            assert not inverted[0] and not inverted[n - 1]
            # d_0 = (rho_N + N FULL) - rho_1 = ~(~(rho_N + N FULL) + rho_1): the first sum's
            # inversion is free in its logic, but for its bits below N FULL's lowest set bit
            # (rho_N's own, an inverter a bit: fewer than rho_1 - rho_N would take)
            values = [difference(~(rho[n - 1] + c.unit), True, rho[0], False)]
            values += [difference(rho[j - 1], inverted[j - 1], rho[j], inverted[j])
                       for j in range(1, n)]
        else:
            values = [Const(0)]
            prefix = rho[0]
            for j in range(1, n):
                values.append((prefix << 1) - c.full * j * (n - j))
                prefix = prefix + rho[j]
        given_inverted = values_held_inverted(n)
        m.d.sync += [self.o_values[j].eq(as_held(values[j], False, j in given_inverted))
                     for j in range(n)]
        m.d.sync += self.o_valid.eq(self.i_valid)
        return m


class ArgMax(wiring.Component):
    """sort2: the position of the largest of ``count`` values, smallest position on ties.

    Only the head of the paper's (N+1)-way duty sort is used (its first column), so sort2 is a
    max-tournament: each stage compares groups of up to ``ARGMAX_GROUP`` entries all-pairs and
    keeps each group's winner, so ``latency = argmax_stages(count)`` (1 for N <= 4).

    Ports
    -----
    i_values : In(ArrayLayout(signed(width), count))
        The candidates; ``i_values[i]`` is the value inverted (``~value``) for ``i`` in
        :func:`values_held_inverted` (as the candidates give them).
    i_valid : In(1)
    o_index : Out(range(count))
        Position of the first maximum of ``i_values`` ``latency`` clocks earlier.
    o_valid : Out(1)

    Parameters
    ----------
    count : int >= 2
    width : int in [2, 64]
    formal : bool
        Emit the properties (``Assert``/``Cover``, no assumption) for the formal tests.
    """

    def __init__(self, count: int, width: int, formal: bool = False):
        validate_positive(count, "count", minimum=2)
        validate_positive(width, "width", minimum=2, maximum=64)
        self.formal = validate_bool(formal, "formal")
        self.count, self.width = count, width
        super().__init__({
            "i_values": In(data.ArrayLayout(signed(width), count)),
            "i_valid": In(1),
            "o_index": Out(range(count)),
            "o_valid": Out(1),
        })

    @property
    def latency(self) -> int:
        return argmax_stages(self.count)

    def elaborate(self, platform):
        m = Module()
        given_inverted = values_held_inverted(self.count)
        # (value as given, given inverted, index); a stage's winners are held as they are
        entries = [(self.i_values[i], i in given_inverted, Const(i, range(self.count)))
                   for i in range(self.count)]
        valid = self.i_valid
        for stage in range(self.latency):
            winners = []
            for g, first in enumerate(range(0, len(entries), ARGMAX_GROUP)):
                group = entries[first:first + ARGMAX_GROUP]
                value = Signal(signed(self.width), name=f"s{stage}_g{g}_value")
                index = Signal(range(self.count), name=f"s{stage}_g{g}_index")
                # Entries of a group are in increasing original position: an earlier one wins
                # ties, a later one must be strictly larger. One compare a pair.
                before = {(i, j): at_least_given(*group[i][:2], *group[j][:2])
                          for i in range(len(group)) for j in range(i + 1, len(group))}
                for i, (v_i, inv_i, x_i) in enumerate(group):
                    wins = Const(1)
                    for j in range(len(group)):
                        if j < i:
                            wins = wins & ~before[j, i]
                        elif j > i:
                            wins = wins & before[i, j]
                    with m.If(wins):
                        m.d.sync += [value.eq(as_held(v_i, inv_i, False)), index.eq(x_i)]
                winners.append((value, False, index))
            next_valid = Signal(name=f"s{stage}_valid")
            m.d.sync += next_valid.eq(valid)
            entries, valid = winners, next_valid
        m.d.comb += [self.o_index.eq(entries[0][2]), self.o_valid.eq(valid)]
        if self.formal:
            self._properties(m)
        return m

    def _properties(self, m):
        """sort2's contract, for any input sequence: ``o_index`` is a candidate index in every
        clock (what the decoder relies on), and a valid one is the first maximum of ``i_values``
        of ``latency`` clocks earlier."""
        m.d.comb += Assert(self.o_index < self.count, "sort2's index is not a candidate")
        delayed_values = delayed(m, self.i_values, self.latency, "formal_values")
        given_inverted = values_held_inverted(self.count)
        values = [as_held(delayed_values[i], i in given_inverted, False) for i in range(self.count)]
        best = Array(values)[self.o_index]
        for i in range(self.count):
            m.d.comb += Assert(
                ~self.o_valid | (values[i] < best) | ((values[i] == best) & (self.o_index <= i)),
                "sort2's index is not the first maximum of its inputs")
        m.d.comb += Cover(self.o_valid & (self.o_index == self.count - 1))


class StateDecoder(wiring.Component):
    """Un-permute the winning staircase column into the gate state, apply the zero policy, and
    compute the state's feedback ``U = N FULL v(h)``. One clock.

    ``h`` has legs ``perm[0..j-1]`` on for ``j > 0``. For the zero class ``j = 0``: all-off, or
    with ``policy = 1`` (fewest transitions) all-on when more than half the legs of ``h_prev`` are
    on. The feedback (the paper's Converter2) is ``U = N FULL v(h) = FULL (N h - k)`` with ``k``
    legs on; it is output in units of ``FULL`` (``N h_i - k``, a small integer), because a
    multiple of ``FULL = 2**(width-2)`` leaves the low ``width - 2`` bits of the integrators
    untouched: the commit then adds only the few bits above them.

    Ports
    -----
    i_perm : In(ArrayLayout(range(phases), phases))
        ``i_perm[p]`` = leg at sorted position ``p`` (sort1's index output).
    i_j : In(range(phases))
        Winning candidate (sort2's output).
    i_policy : In(1)
        Zero-state policy: 0 all-off, 1 fewest transitions.
    i_h_prev : In(phases)
        The state output by the previous update.
    i_valid : In(1)
    o_h : Out(phases)
        Gate state, bit i = leg i upper switch on.
    o_units_n : Out(ArrayLayout(signed(units_width), phases))
        Feedback of ``o_h`` divided by ``FULL``, given inverted: ``~(N h_i - k)``, with
        ``N h_i - k`` in [-(N-1), N-1] (the integrators subtract it: an addition of the value
        as given). 0 as given after a reset (read only with ``o_valid``).
    o_valid : Out(1)

    Parameters
    ----------
    phases : int >= 3
    formal : bool
        Emit contract property 6 (``Assert``/``Cover``) for the formal tests.
    assume_inputs : bool
        With ``formal``: assume what sort1 and sort2 guarantee (``i_perm`` a permutation,
        ``i_j < phases``), to prove the block alone. Off inside the core, where those blocks'
        own assertions prove it in the same run.
    """

    latency = 1

    def __init__(self, phases: int, formal: bool = False, assume_inputs: bool = True):
        validate_positive(phases, "phases", minimum=3)
        self.formal = validate_bool(formal, "formal")
        self.assume_inputs = validate_bool(assume_inputs, "assume_inputs")
        self.phases = phases
        self.units_width = signed_bits(-(phases - 1), phases - 1)
        super().__init__({
            "i_perm": In(data.ArrayLayout(range(phases), phases)),
            "i_j": In(range(phases)),
            "i_policy": In(1),
            "i_h_prev": In(phases),
            "i_valid": In(1),
            "o_h": Out(phases),
            "o_units_n": Out(data.ArrayLayout(signed(self.units_width), phases)),
            "o_valid": Out(1),
        })

    def elaborate(self, platform):
        m = Module()
        n = self.phases
        legs = []
        for leg in range(n):
            on = Const(0)
            for position in range(n - 1):       # position n-1 is never on for j <= n-1
                on = on | ((self.i_j > position) & (self.i_perm[position] == leg))
            legs.append(on)
        prev_on = sum(self.i_h_prev[i] for i in range(n))
        all_on = self.i_policy & (prev_on * 2 > n)
        h = Signal(n)
        m.d.comb += h.eq(Mux(self.i_j == 0, Mux(all_on, (1 << n) - 1, 0), Cat(*legs)))
        # the feedback N h_i - k of the zero class is 0 whichever state the policy picks (all
        # on: N - N; all off: 0 - 0), so it does not wait for the policy: the previous state's
        # count and its compare were the Fmax path into the feedback at N = 9
        m.d.sync += [self.o_units_n[i].eq(~Mux(self.i_j == 0, 0, Mux(legs[i], n, 0) - self.i_j))
                     for i in range(n)]
        m.d.sync += [self.o_h.eq(h), self.o_valid.eq(self.i_valid)]
        if self.formal:
            self._properties(m)
        return m

    def _properties(self, m):
        """Contract property 6: the state is a member of the candidate set of its inputs (the
        staircase column j of the permutation, or all-off / all-on for j = 0) and the feedback is
        exactly its phase voltage, for any permutation, winner and previous state."""
        n = self.phases
        if self.assume_inputs:      # what sort1 and sort2 assert in every clock
            m.d.comb += [Assume(is_permutation([self.i_perm[p] for p in range(n)], n)),
                         Assume(self.i_j < n)]
        perm = Signal(data.ArrayLayout(range(n), n), reset_less=True)
        j = Signal(range(n), reset_less=True)
        started = Signal(reset_less=True)
        rst_prev = Signal(reset_less=True)
        m.d.sync += [perm.eq(self.i_perm), j.eq(self.i_j), started.eq(1),
                     rst_prev.eq(ResetSignal())]
        staircase = Cat(*[Cat(*[(p < j) & (perm[p] == leg) for p in range(n)]).any()
                          for leg in range(n)])
        count = sum(self.o_h[i] for i in range(n))
        in_set = Mux(j == 0, (self.o_h == 0) | (self.o_h == (1 << n) - 1),
                     self.o_h == staircase)
        m.d.comb += Assert(~started | rst_prev | in_set,
                           "state outside the candidate set of its inputs")
        for i in range(n):
            m.d.comb += Assert(~started | rst_prev
                               | (~self.o_units_n[i] == Mux(self.o_h[i], n, 0) - count),
                               "feedback is not the phase voltage of the state")
        # every one of the 2**N gate states is reached (all-on through the zero policy)
        m.d.comb += [Cover(self.o_valid & ~rst_prev & (self.o_h == state))
                     for state in range(1 << n)]
