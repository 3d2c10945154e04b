"""N-phase sine reference: phase accumulator, quarter- or full-wave sine table, amplitude.

The specification, bit for bit and clock for clock, is :mod:`mdfqm_model.nco`.
"""

from amaranth import Array, Cat, Const, Module, Mux, Signal, signed, unsigned
from amaranth.lib import data, stream, wiring
from amaranth.lib.memory import Memory
from amaranth.lib.wiring import In, Out

from mdfqm_spec.contract import Contract
from mdfqm_spec.nco import beat_clocks, phase_offsets, sine_quarter, sine_table, validate_nco

__all__ = ["SineNco"]


class SineNco(wiring.Component):
    """Reference codes of an N-phase sine of runtime frequency and amplitude.

    One table read port and one serial shift-add multiplier are shared by the phases, so the
    block is small on any FPGA (no DSP); a beat takes ``1 + N (sample_width + 2)`` clocks
    (:mod:`mdfqm_model.nco`, "Clock-level timing"): the sign is applied in a clock of its own,
    so that the multiplier's carry chain and the negation's are not one path.

    Ports
    -----
    freq : In(acc_bits)
        Phase increment per clock: ``f_out = freq * f_clk / 2**acc_bits``. Read every clock.
    amplitude : In(width - 1)
        Peak code of every phase (``FULL = 2**(width-2)`` codes per Vdc); taken at the start of
        each beat.
    ref : Out(stream.Signature(ArrayLayout(signed(width), phases)))
        Phase references for the core (registered); phase ``i`` lags phase 0 by ``i/N`` turn.
    phase : Out(acc_bits)
        The phase accumulator (registered); its MSB is a square wave in phase with phase 0.

    Parameters
    ----------
    phases, width : int
        As the core (``width`` in ``[min_width(phases), 32]``).
    acc_bits : int in [table_bits + 2, 32]
    table_bits : int in [2, 12]
        ``2**table_bits`` table entries per quarter wave.
    sample_width : int in [4, 24]
        Signed width of the table samples (peak ``2**(sample_width-1) - 1``).
    quarter : bool
        Store a quarter wave (``2**table_bits`` words) and mirror it, or the full wave.
    """

    def __init__(self, phases: int = 3, width: int = 16, acc_bits: int = 32,
                 table_bits: int = 8, sample_width: int = 16, quarter: bool = True):
        Contract(phases, width)
        validate_nco(acc_bits, table_bits, sample_width)
        if not isinstance(quarter, bool):
            raise ValueError(f"quarter must be a bool, not {quarter!r}")
        self.phases, self.width, self.acc_bits = phases, width, acc_bits
        self.table_bits, self.sample_width, self.quarter = table_bits, sample_width, quarter
        self.beat_clocks = beat_clocks(phases, sample_width)
        super().__init__({
            "freq": In(acc_bits),
            "amplitude": In(width - 1),
            "ref": Out(stream.Signature(data.ArrayLayout(signed(width), phases))),
            "phase": Out(acc_bits),
        })

    def elaborate(self, platform):
        m = Module()
        n, tb, sw, w = self.phases, self.table_bits, self.sample_width, self.width
        mag_bits = sw - 1
        if self.quarter:
            values = [int(v) for v in sine_quarter(tb, sw)]
            m.submodules.table = table = Memory(shape=unsigned(mag_bits), depth=1 << tb,
                                                init=values)
        else:
            values = [int(v) for v in sine_table(tb, sw)]
            m.submodules.table = table = Memory(shape=signed(sw), depth=4 << tb, init=values)
        rd = table.read_port()

        m.d.sync += self.phase.eq(self.phase + self.freq)

        base = Signal(self.acc_bits)
        amp = Signal(w - 1)
        k = Signal(range(n))
        negative = Signal()
        mag = Signal(mag_bits)
        bit = Signal(range(mag_bits))
        product = Signal(w - 1 + mag_bits)
        offsets = Array(Const(o, self.acc_bits) for o in phase_offsets(n, self.acc_bits))

        angle = (base + offsets[k])[:self.acc_bits]
        index = angle[self.acc_bits - tb - 2:]
        quadrant = index[tb:]
        if self.quarter:
            j = index[:tb]
            m.d.comb += rd.addr.eq(Mux(quadrant[0], ~j, j))
            sample_mag, sample_neg = rd.data, quadrant[1]
        else:
            m.d.comb += rd.addr.eq(index)
            sample_neg = rd.data[-1]
            sample_mag = Mux(sample_neg, -rd.data, rd.data)[:mag_bits]

        with m.FSM():
            with m.State("IDLE"):
                with m.If(self.ref.valid & self.ref.ready):
                    m.d.sync += self.ref.valid.eq(0)
                with m.Elif(~self.ref.valid):
                    m.d.sync += [base.eq(self.phase), amp.eq(self.amplitude), k.eq(0)]
                    m.next = "ADDRESS"
            with m.State("ADDRESS"):        # the table reads rd.addr (base and k hold)
                m.next = "LOAD"
            with m.State("LOAD"):
                m.d.sync += [
                    mag.eq(sample_mag),
                    negative.eq(sample_neg),
                    product.eq(0),
                    bit.eq(mag_bits - 1),
                ]
                m.next = "MULTIPLY"
            with m.State("MULTIPLY"):
                # shift-and-add from the magnitude's LSB: the amplitude is added to the top
                # width - 1 bits only (a short carry chain; the low bits shift through), and
                # the product is the same exact amp * mag after mag_bits steps
                high = product[mag_bits:] + Mux(mag[0], amp, 0)
                step = Cat(product[1:mag_bits], high)
                m.d.sync += [product.eq(step), mag.eq(mag >> 1), bit.eq(bit - 1)]
                with m.If(bit == 0):
                    m.next = "STORE"
            with m.State("STORE"):          # the product's high part is the code's magnitude
                code = product[mag_bits:]
                m.d.sync += [self.ref.payload[k].eq(Mux(negative, -code, code)), k.eq(k + 1)]
                m.next = "ADDRESS"
                with m.If(k == n - 1):
                    m.d.sync += self.ref.valid.eq(1)
                    m.next = "IDLE"
        return m
