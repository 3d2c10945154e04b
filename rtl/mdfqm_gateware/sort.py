"""sort1: the pipelined N-input sorting network."""

from amaranth import C, Cat, Module, Mux, Signal, signed
from amaranth.lib import data, wiring
from amaranth.lib.wiring import In, Out

from mdfqm_model.contract import sorting_network

from .arith import greater


def validate_count(count: int, name: str = "count", minimum: int = 2) -> None:
    if not isinstance(count, int) or count < minimum:
        raise ValueError(f"{name} must be an integer >= {minimum}, not {count!r}")


def validate_width(width: int, name: str = "width") -> None:
    if not isinstance(width, int) or not 2 <= width <= 64:
        raise ValueError(f"{name} must be an integer in [2, 64], not {width!r}")


class SortNetwork(wiring.Component):
    """Sort ``count`` signed values descending, one comparator layer per clock.

    The network is :func:`mdfqm_model.contract.sorting_network` (Batcher's odd-even merge sort,
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

    Parameters
    ----------
    count : int >= 2
    width : int in [2, 64]

    Attributes
    ----------
    latency : int
        Clocks from input to output: the network's depth (3 for three inputs).
    """

    def __init__(self, count: int, width: int):
        validate_count(count)
        validate_width(width)
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
        for layer_no, layer in enumerate(self.layers):
            next_values = [Signal(signed(self.width), name=f"l{layer_no}_value{i}")
                           for i in range(self.count)]
            next_index = [Signal(range(self.count), name=f"l{layer_no}_index{i}")
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
        for i in range(self.count):
            m.d.comb += [self.o_values[i].eq(values[i]), self.o_index[i].eq(index[i])]
        m.d.comb += self.o_valid.eq(valid)
        return m
