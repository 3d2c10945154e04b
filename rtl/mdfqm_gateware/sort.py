"""sort1: the pipelined N-input sorting network."""

from amaranth import Array, C, Cat, Module, Mux, Signal, signed
from amaranth.hdl import Assert, Cover
from amaranth.lib import data, wiring
from amaranth.lib.wiring import In, Out

from mdfqm_spec.contract import sorting_network
from mdfqm_spec.validate import validate_bool, validate_positive

from .arith import as_held, greater
from .properties import is_permutation

__all__ = ["SortNetwork"]


def _first(value_a, index_a, inverted_a, value_b, index_b, inverted_b):
    """``a`` sorts before ``b``: its key ``(value, -index)`` is the larger (keys are distinct).

    Each value is given as held, inverted or not. A compare is a subtraction, which needs one
    operand inverted; when one is held inverted and the other is not, it is an addition of the
    two as they are (on the iCE40 an inverter in front of a carry chain is a LUT a bit).
    The key is ``Cat(~index, value)``, so the inverted key is ``Cat(index, ~value)``."""
    key_a = Cat(~index_a, ~value_a if inverted_a else value_a).as_signed()
    key_b = Cat(~index_b, ~value_b if inverted_b else value_b).as_signed()
    # distinct keys: key_a > key_b is key_a - key_b - 1 >= 0, and key_b - key_a - 1 < 0
    if inverted_a and not inverted_b:
        return (key_b + Cat(index_a, value_a).as_signed())[-1]
    if inverted_b and not inverted_a:
        return ~(key_a + Cat(index_b, value_b).as_signed())[-1]
    return greater(key_a, key_b)


def held_inverted(layers, count: int, outputs=frozenset()) -> list[list[bool]]:
    """Which register of each layer holds its value inverted: ``result[layer][position]``.

    A comparator wants its operands held one inverted and one not (:func:`_first`). A position
    a comparator writes may be held either way at no cost (the inversion is in its
    multiplexer); a position no comparator of the layer writes is a copy, held as before. So a
    written position is held opposite to the partner of the next comparator that reads it if
    that partner's way is known by then, else inverted (the partner, written later, then
    follows it); and as its output is given (inverted for a position in ``outputs``) if
    nothing reads it again. The inputs are held as they are: only comparators whose operands
    both come unwritten from the inputs (the first layer's) need an inverter."""
    written = [{i for pair in layer for i in pair} for layer in layers]
    result: list[list[bool | None]] = [[None] * count for _ in layers]     # None: not yet known

    def held_as_read(position, layer_no):
        """How ``position``'s value is held as layer ``layer_no`` reads it (None: not known)."""
        for earlier in range(layer_no - 1, -1, -1):
            if position in written[earlier]:
                return result[earlier][position]
        return False

    def next_partner(position, layer_no):
        """(partner, layer) of the next comparator after ``layer_no`` that reads ``position``."""
        for later in range(layer_no + 1, len(layers)):
            for a, b in layers[later]:
                if position in (a, b):
                    return (b if position == a else a), later
        return None, None

    for layer_no in range(len(layers)):
        for position in range(count):
            if position not in written[layer_no]:
                result[layer_no][position] = held_as_read(position, layer_no)
        for position in sorted(written[layer_no]):
            partner, read_at = next_partner(position, layer_no)
            if partner is None:
                result[layer_no][position] = position in outputs
            else:
                partner_held = held_as_read(partner, read_at)
                result[layer_no][position] = True if partner_held is None else not partner_held
    return result


class SortNetwork(wiring.Component):
    """Sort ``count`` signed values descending, one comparator layer per clock.

    The network is :func:`mdfqm_spec.contract.sorting_network` (Batcher's odd-even merge sort,
    pruned to ``count`` inputs). Each comparator orders by the key ``(-value, input index)``, so
    equal values keep input order and the result is the unique stable descending sort, whatever
    the network's shape: exactly the model's ``sort1``.

    Ports
    -----
    i_values : In(ArrayLayout(signed(width), count))
        Values to sort; sampled every clock.
    i_valid : In(1)
        Marks a valid input; travels with the data.
    o_values : Out(ArrayLayout(signed(width), count))
        ``i_values`` of ``latency`` clocks earlier, sorted descending (o_values[0] largest);
        for a position ``p`` in ``inverted_outputs``, ``o_values[p]`` is that value inverted
        (``~value``, for a consumer that subtracts it).
    o_index : Out(ArrayLayout(unsigned, count))
        ``o_index[p]`` is the input position whose value is at sorted position ``p``.
    o_valid : Out(1)
        ``i_valid`` delayed by ``latency`` clocks.

    After a reset every layer holds the identity permutation, so ``o_index`` is a permutation
    in every clock (what the decoder relies on). The values the layers hold then are not
    inputs (some registers hold their values inverted, and every register resets to 0 as
    held): for ``latency`` clocks after a reset ``o_values`` and ``o_index`` are unspecified
    (``o_valid`` is low), and from then on they are the inputs' sort, whatever ``i_valid``.

    Parameters
    ----------
    count : int >= 2
    width : int in [2, 64]
    inverted_outputs : iterable of positions
        The outputs given inverted (default none).
    formal : bool
        Emit the properties (``Assert``/``Cover``, no assumption) for the formal tests.

    Attributes
    ----------
    latency : int
        Clocks from input to output: the network's depth (3 for three inputs).
    """

    def __init__(self, count: int, width: int, formal: bool = False, inverted_outputs=()):
        validate_positive(count, "count", minimum=2)
        validate_positive(width, "width", minimum=2, maximum=64)
        self.formal = validate_bool(formal, "formal")
        inverted_outputs = frozenset(inverted_outputs)
        if not inverted_outputs <= set(range(count)):
            raise ValueError(f"inverted_outputs must be positions in [0, {count - 1}], not "
                             f"{sorted(inverted_outputs)!r}")
        self.inverted_outputs = inverted_outputs
        self.count = count
        self.width = width
        self.layers = sorting_network(count)
        index_shape = range(count)
        super().__init__({
            "i_values": In(data.ArrayLayout(signed(width), count)),
            "i_valid": In(1),
            "o_values": Out(data.ArrayLayout(signed(width), count)),
            "o_index": Out(data.ArrayLayout(index_shape, count)),
            "o_valid": Out(1),
        })

    @property
    def latency(self) -> int:
        return len(self.layers)

    def elaborate(self, platform):
        m = Module()
        values = [self.i_values[i] for i in range(self.count)]
        inverted = [False] * self.count         # how each of ``values`` is held
        index = [C(i, range(self.count)) for i in range(self.count)]
        valid = self.i_valid
        stages = []         # each layer's registers (their values as they are), for the properties
        polarities = held_inverted(self.layers, self.count, self.inverted_outputs)
        for layer_no, layer in enumerate(self.layers):
            next_inverted = polarities[layer_no]
            # reset to 0 as held (a value held inverted: -1): an iCE40 flop powers up at 0,
            # and one that resets to 1 is built inverted, with a LUT on each side
            next_values = [Signal(signed(self.width), name=f"l{layer_no}_value{i}")
                           for i in range(self.count)]

            # reset to the identity: o_index is a permutation in every clock, even the first
            next_index = [Signal(range(self.count), init=i, name=f"l{layer_no}_index{i}")
                          for i in range(self.count)]
            touched = set()
            for a, b in layer:
                touched.update((a, b))
                # One compare of the key (value, inverted index): larger value first, lower
                # input index first among equal values. Keys are distinct, so the order is total.
                a_first = _first(values[a], index[a], inverted[a], values[b], index[b],
                                 inverted[b])
                m.d.sync += [
                    next_values[a].eq(Mux(a_first, *[
                        as_held(values[i], inverted[i], next_inverted[a]) for i in (a, b)])),
                    next_values[b].eq(Mux(a_first, *[
                        as_held(values[i], inverted[i], next_inverted[b]) for i in (b, a)])),
                    next_index[a].eq(Mux(a_first, index[a], index[b])),
                    next_index[b].eq(Mux(a_first, index[b], index[a])),
                ]
            for i in set(range(self.count)) - touched:
                m.d.sync += [next_values[i].eq(values[i]), next_index[i].eq(index[i])]
            next_valid = Signal(name=f"l{layer_no}_valid")
            m.d.sync += next_valid.eq(valid)
            values, index, valid = next_values, next_index, next_valid
            inverted = next_inverted
            stages.append(([as_held(v, inv, False) for v, inv in zip(values, inverted,
                                                                     strict=True)], index))
        for i in range(self.count):
            m.d.comb += [
                self.o_values[i].eq(as_held(values[i], inverted[i],
                                             i in self.inverted_outputs)),
                self.o_index[i].eq(index[i]),
            ]
        m.d.comb += self.o_valid.eq(valid)
        if self.formal:
            self._properties(m, stages, polarities)
        return m

    def _properties(self, m, stages, polarities):
        """sort1's contract, for any input sequence: ``o_index`` is a permutation in every clock
        (what the decoder relies on), and a valid output is ``i_values`` of ``latency`` clocks
        earlier permuted by ``o_index``, descending, equal values in input order."""
        n = self.count
        # Every layer holds a permutation and the inputs of as many clocks earlier, permuted by
        # it (both inductive layer by layer: the registers and the copies reset together).
        source = self.i_values
        for layer_no, (values, index) in enumerate(stages):
            # the copies reset with the layer's registers, to the values these reset to
            copy = Signal(data.ArrayLayout(signed(self.width), n),
                          init=[-int(inverted) for inverted in polarities[layer_no]],
                          name=f"formal_values_l{layer_no}")
            m.d.sync += copy.eq(source)
            source = copy
            sources = Array(source[i] for i in range(n))
            m.d.comb += Assert(is_permutation(index, n), "sort1's index is not a permutation")
            for p in range(n):
                m.d.comb += Assert(values[p] == sources[index[p]],
                                   "sort1's values are not its inputs permuted by its index")
        # sorted once the whole network has been passed (k-induction depth >= latency + 1)
        for p in range(n - 1):
            first, second = stages[-1][0][p], stages[-1][0][p + 1]
            m.d.comb += Assert(
                ~self.o_valid | (first > second)
                | ((first == second) & (self.o_index[p] < self.o_index[p + 1])),
                "sort1's output is not descending with ties in input order")
        m.d.comb += Cover(self.o_valid & (self.o_index[0] == n - 1))
