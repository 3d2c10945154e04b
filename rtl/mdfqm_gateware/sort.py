"""sort1: the pipelined N-input sorting network."""

from amaranth import Array, C, Cat, Module, Mux, Signal, signed
from amaranth.hdl import Assert, Cover
from amaranth.lib import data, wiring
from amaranth.lib.wiring import In, Out

from mdfqm_spec.contract import sorting_network
from mdfqm_spec.validate import validate_bool, validate_positive

from .arith import greater
from .properties import delayed, is_permutation

__all__ = ["SortNetwork"]


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
        ``i_values`` of ``latency`` clocks earlier, sorted descending (o_values[0] largest).
    o_index : Out(ArrayLayout(unsigned, count))
        ``o_index[p]`` is the input position whose value is at sorted position ``p``.
    o_valid : Out(1)
        ``i_valid`` delayed by ``latency`` clocks.

    After a reset the pipeline holds the sort of all-zero values (values 0, the identity
    permutation), so ``o_index`` is a permutation in every clock.

    Parameters
    ----------
    count : int >= 2
    width : int in [2, 64]
    formal : bool
        Emit the properties (``Assert``/``Cover``, no assumption) for the formal tests.

    Attributes
    ----------
    latency : int
        Clocks from input to output: the network's depth (3 for three inputs).
    """

    def __init__(self, count: int, width: int, formal: bool = False):
        validate_positive(count, "count", minimum=2)
        validate_positive(width, "width", minimum=2, maximum=64)
        self.formal = validate_bool(formal, "formal")
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
        index = [C(i, range(self.count)) for i in range(self.count)]
        valid = self.i_valid
        stages = []         # each layer's registers, for the properties
        for layer_no, layer in enumerate(self.layers):
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
                key_a = Cat(~index[a], values[a]).as_signed()
                key_b = Cat(~index[b], values[b]).as_signed()
                a_first = greater(key_a, key_b)
                m.d.sync += [
                    next_values[a].eq(Mux(a_first, values[a], values[b])),
                    next_values[b].eq(Mux(a_first, values[b], values[a])),
                    next_index[a].eq(Mux(a_first, index[a], index[b])),
                    next_index[b].eq(Mux(a_first, index[b], index[a])),
                ]
            for i in set(range(self.count)) - touched:
                m.d.sync += [next_values[i].eq(values[i]), next_index[i].eq(index[i])]
            next_valid = Signal(name=f"l{layer_no}_valid")
            m.d.sync += next_valid.eq(valid)
            values, index, valid = next_values, next_index, next_valid
            stages.append((values, index))
        for i in range(self.count):
            m.d.comb += [self.o_values[i].eq(values[i]), self.o_index[i].eq(index[i])]
        m.d.comb += self.o_valid.eq(valid)
        if self.formal:
            self._properties(m, stages)
        return m

    def _properties(self, m, stages):
        """sort1's contract, for any input sequence: ``o_index`` is a permutation in every clock
        (what the decoder relies on), and a valid output is ``i_values`` of ``latency`` clocks
        earlier permuted by ``o_index``, descending, equal values in input order."""
        n = self.count
        # Every layer holds a permutation and the inputs of as many clocks earlier, permuted by
        # it (both inductive layer by layer: the registers and the copies reset together).
        source = self.i_values
        for layer_no, (values, index) in enumerate(stages):
            source = delayed(m, source, 1, f"formal_values_l{layer_no}", reset_less=False)
            sources = Array(source[i] for i in range(n))
            m.d.comb += Assert(is_permutation(index, n), "sort1's index is not a permutation")
            for p in range(n):
                m.d.comb += Assert(values[p] == sources[index[p]],
                                   "sort1's values are not its inputs permuted by its index")
        # sorted once the whole network has been passed (k-induction depth >= latency + 1)
        for p in range(n - 1):
            first, second = self.o_values[p], self.o_values[p + 1]
            m.d.comb += Assert(
                ~self.o_valid | (first > second)
                | ((first == second) & (self.o_index[p] < self.o_index[p + 1])),
                "sort1's output is not descending with ties in input order")
        m.d.comb += Cover(self.o_valid & (self.o_index[0] == n - 1))
