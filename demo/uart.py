"""8N1 UART: a receiver and a transmitter with a fixed number of clocks per bit.

Timing, clock by clock (what :mod:`tb.demo_models` predicts):

Transmitter
    ``i.ready`` is high when idle and in the last clock of a stop bit. A byte accepted in cycle
    ``a`` puts the start bit on ``tx`` from cycle ``a + 1`` for ``divider`` clocks, then the eight
    data bits LSB first and one stop bit, ``divider`` clocks each: a continuous stream takes
    exactly ``10 * divider`` clocks per byte.
Receiver
    ``rx`` passes a two-flip-flop synchroniser (reset to 1): ``rx_s`` in cycle ``c`` is ``rx`` of
    cycle ``c - 2``. A cycle ``s`` in the idle state with ``rx_s == 0`` starts a frame; the start
    bit is checked at ``s + divider // 2`` (high there: a glitch, back to idle) and the data bits
    and the stop bit are sampled ``divider`` clocks apart after it. A high stop bit delivers the
    byte on ``o`` from the next cycle (held until ``o.ready``); if the previous byte is still
    waiting the new one is dropped and ``overrun`` pulses. A low stop bit pulses ``frame_error``
    and the receiver waits for ``rx_s == 1`` before it looks for the next start bit.
"""

from amaranth import Cat, Module, Signal
from amaranth.lib import stream, wiring
from amaranth.lib.wiring import In, Out

from mdfqm_spec.validate import validate_positive

__all__ = ["DIVIDER_MAX", "DIVIDER_MIN", "UartRx", "UartTx", "uart_divider"]

DIVIDER_MIN = 4
DIVIDER_MAX = 1 << 16
#: largest relative baud-rate error :func:`uart_divider` accepts (8N1 tolerates about 4 %)
BAUD_TOLERANCE = 0.02


def validate_divider(divider) -> int:
    return validate_positive(divider, "divider", minimum=DIVIDER_MIN, maximum=DIVIDER_MAX)


def uart_divider(clk_hz, baud) -> int:
    """Clocks per bit for ``baud`` from a ``clk_hz`` clock, rounded; ``ValueError`` if the
    resulting rate is more than 2 % off or the divider is out of range."""
    if not isinstance(clk_hz, (int, float)) or isinstance(clk_hz, bool) or clk_hz <= 0:
        raise ValueError(f"clk_hz must be a positive number, not {clk_hz!r}")
    if not isinstance(baud, (int, float)) or isinstance(baud, bool) or baud <= 0:
        raise ValueError(f"baud must be a positive number, not {baud!r}")
    divider = round(clk_hz / baud)
    if not DIVIDER_MIN <= divider <= DIVIDER_MAX:
        raise ValueError(
            f"baud {baud} needs {clk_hz / baud:.2f} clocks per bit at {clk_hz} Hz; "
            f"the divider must be in [{DIVIDER_MIN}, {DIVIDER_MAX}]")
    error = abs(clk_hz / divider - baud) / baud
    if error > BAUD_TOLERANCE:
        raise ValueError(
            f"baud {baud} is {100 * error:.1f} % off at {clk_hz} Hz (divider {divider}); "
            f"at most {100 * BAUD_TOLERANCE:.0f} % is allowed")
    return divider


class UartTx(wiring.Component):
    """8N1 transmitter.

    Ports
    -----
    i : In(stream.Signature(8))
        Bytes to send. ``i.ready`` is combinational from registers only.
    tx : Out(1)
        Serial line, idle high (registered).
    busy : Out(1)
        A frame is on the line (start, data or stop bit).

    Parameters
    ----------
    divider : int in [4, 65536]
        Clocks per bit (see :func:`uart_divider`).
    """

    def __init__(self, divider: int):
        self.divider = validate_divider(divider)
        super().__init__({
            "i": In(stream.Signature(8)),
            "tx": Out(1, init=1),
            "busy": Out(1),
        })

    def elaborate(self, platform):
        m = Module()
        d = self.divider
        count = Signal(range(d))       # clocks left in the current bit, minus one
        left = Signal(range(11))       # bits of the frame not finished, the current one included
        shreg = Signal(9)              # data bits then the stop bit, LSB first
        # ``count == 0`` held in a register (set where the count steps down from 1; both reset
        # together), so that the handshake and the count's reload do not wait for a compare
        last_clock = Signal(init=1)

        m.d.comb += [
            self.i.ready.eq((left == 0) | ((left == 1) & last_clock)),
            self.busy.eq(left != 0),
        ]
        with m.If(self.i.valid & self.i.ready):
            m.d.sync += [
                self.tx.eq(0),
                shreg.eq(Cat(self.i.payload, 1)),
                left.eq(10),
                count.eq(d - 1),
                last_clock.eq(0),
            ]
        with m.Elif(left != 0):
            with m.If(last_clock):
                m.d.sync += [
                    left.eq(left - 1),
                    count.eq(d - 1),
                    last_clock.eq(0),
                    self.tx.eq((left == 1) | shreg[0]),
                    shreg.eq(shreg >> 1),
                ]
            with m.Else():
                m.d.sync += [count.eq(count - 1), last_clock.eq(count == 1)]
        return m


class UartRx(wiring.Component):
    """8N1 receiver with a two-flip-flop synchroniser, mid-bit sampling and error flags.

    Ports
    -----
    rx : In(1)
        Serial line (asynchronous to the clock; idle high).
    o : Out(stream.Signature(8))
        Received bytes (registered); a byte is held until ``o.ready``.
    overrun : Out(1)
        One-clock pulse: a byte arrived while the previous one was still held; it was dropped.
    frame_error : Out(1)
        One-clock pulse: the stop bit was low; the byte was dropped.

    Parameters
    ----------
    divider : int in [4, 65536]
        Clocks per bit (see :func:`uart_divider`).
    """

    def __init__(self, divider: int):
        self.divider = validate_divider(divider)
        super().__init__({
            "rx": In(1, init=1),
            "o": Out(stream.Signature(8)),
            "overrun": Out(1),
            "frame_error": Out(1),
        })

    def elaborate(self, platform):
        m = Module()
        d = self.divider
        sync1 = Signal(init=1)
        rx_s = Signal(init=1)
        m.d.sync += [sync1.eq(self.rx), rx_s.eq(sync1)]

        count = Signal(range(d))
        bit = Signal(range(8))
        shreg = Signal(8)
        new_byte = Signal()
        m.d.sync += [self.overrun.eq(0), self.frame_error.eq(0)]

        with m.FSM():
            with m.State("IDLE"):
                with m.If(~rx_s):
                    m.d.sync += count.eq(d // 2 - 1)
                    m.next = "START"
            with m.State("START"):
                with m.If(count == 0):
                    m.d.sync += [count.eq(d - 1), bit.eq(0)]
                    m.next = "DATA"
                    with m.If(rx_s):
                        m.next = "IDLE"
                with m.Else():
                    m.d.sync += count.eq(count - 1)
            with m.State("DATA"):
                with m.If(count == 0):
                    m.d.sync += [count.eq(d - 1), bit.eq(bit + 1), shreg.eq(Cat(shreg[1:], rx_s))]
                    with m.If(bit == 7):
                        m.next = "STOP"
                with m.Else():
                    m.d.sync += count.eq(count - 1)
            with m.State("STOP"):
                with m.If(count == 0):
                    with m.If(rx_s):
                        m.d.comb += new_byte.eq(1)
                        m.next = "IDLE"
                    with m.Else():
                        m.d.sync += self.frame_error.eq(1)
                        m.next = "WAIT_HIGH"
                with m.Else():
                    m.d.sync += count.eq(count - 1)
            with m.State("WAIT_HIGH"):
                with m.If(rx_s):
                    m.next = "IDLE"

        held = self.o.valid & ~self.o.ready
        with m.If(new_byte & held):
            m.d.sync += self.overrun.eq(1)
        with m.Elif(new_byte):
            m.d.sync += [self.o.valid.eq(1), self.o.payload.eq(shreg)]
        with m.Elif(self.o.ready):
            m.d.sync += self.o.valid.eq(0)
        return m
