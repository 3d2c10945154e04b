"""Cycle models of the board-demo blocks, written from the timing stated in their docstrings.

Every model has ``outputs()`` (what is visible during the current cycle, a function of its
registers) and ``step(**inputs)`` (returns ``outputs()`` of this cycle, then advances one clock),
like :class:`mdfqm_model.clock.CoreModel`. Pure Python: the cocotb tests generate their stimulus
with the model in the loop, then compare the RTL with it on every clock (harness.check_cycles).
"""

from __future__ import annotations

__all__ = ["UartRxModel", "UartTxModel", "line_bits"]


def line_bits(byte: int, divider: int, stop: int = 1) -> list[int]:
    """Line levels of one 8N1 frame, ``divider`` clocks per bit (start, data LSB first, stop)."""
    bits = [0] + [(byte >> i) & 1 for i in range(8)] + [stop]
    return [b for b in bits for _ in range(divider)]


class UartTxModel:
    """:class:`demo.uart.UartTx`: ``step(valid, payload)``."""

    def __init__(self, divider: int):
        self.divider = divider
        self.tx, self.count, self.left, self.shreg = 1, 0, 0, 0

    def outputs(self) -> dict:
        ready = int(self.left == 0 or (self.left == 1 and self.count == 0))
        return {"ready": ready, "tx": self.tx, "busy": int(self.left != 0)}

    def step(self, valid: int = 0, payload: int = 0) -> dict:
        out = self.outputs()
        if valid and out["ready"]:
            self.tx, self.shreg, self.left, self.count = 0, payload | 0x100, 10, self.divider - 1
        elif self.left:
            if self.count == 0:
                self.tx = 1 if self.left == 1 else self.shreg & 1
                self.shreg >>= 1
                self.left -= 1
                self.count = self.divider - 1
            else:
                self.count -= 1
        return out


class UartRxModel:
    """:class:`demo.uart.UartRx`: ``step(rx, ready)``."""

    def __init__(self, divider: int):
        self.divider = divider
        self.sync = [1, 1]             # sync1, rx_s
        self.state, self.count, self.bit, self.shreg = "IDLE", 0, 0, 0
        self.valid, self.payload, self.overrun, self.frame_error = 0, 0, 0, 0

    def outputs(self) -> dict:
        return {"valid": self.valid, "payload": self.payload, "overrun": self.overrun,
                "frame_error": self.frame_error}

    def step(self, rx: int = 1, ready: int = 0) -> dict:
        out = self.outputs()
        d, rx_s = self.divider, self.sync[1]
        self.sync = [rx, self.sync[0]]
        self.overrun = self.frame_error = 0
        new_byte = False
        state = self.state
        if state == "IDLE":
            if not rx_s:
                self.count, self.state = d // 2 - 1, "START"
        elif state == "WAIT_HIGH":
            if rx_s:
                self.state = "IDLE"
        elif self.count:
            self.count -= 1
        elif state == "START":
            self.count, self.bit = d - 1, 0
            self.state = "IDLE" if rx_s else "DATA"
        elif state == "DATA":
            self.count = d - 1
            self.shreg = (self.shreg >> 1) | (rx_s << 7)
            self.bit = (self.bit + 1) % 8
            if self.bit == 0:
                self.state = "STOP"
        elif rx_s:                                   # STOP, sampled high
            new_byte, self.state = True, "IDLE"
        else:                                        # STOP, sampled low
            self.frame_error, self.state = 1, "WAIT_HIGH"
        if new_byte and out["valid"] and not ready:
            self.overrun = 1
        elif new_byte:
            self.valid, self.payload = 1, self.shreg
        elif ready:
            self.valid = 0
        return out


class BridgeModel:
    """:class:`demo.bridge.UartBridge`:
    ``step(rx_valid, rx_payload, tx_ready, ack, dat_r)``."""

    W, R, E, T = ord("W"), ord("R"), ord("E"), ord("T")

    def __init__(self, addr_width=16, bus_timeout=64, frame_timeout=30_000):
        self.addr_mask = (1 << addr_width) - 1
        self.bus_timeout, self.frame_timeout = bus_timeout, frame_timeout
        self.state = "RECEIVE"
        self.cmd = self.addr = self.data = self.status = 0
        self.count = self.total = self.timer = self.index = 0
        self.cyc = self.we = 0
        self.checksum_error = self.bus_timeout_error = 0

    def reply_byte(self) -> int:
        fields = [self.status, self.addr >> 8, self.addr & 0xFF, *self.data.to_bytes(4, "big"),
                  -self.total & 0xFF]
        return fields[self.index]

    def outputs(self) -> dict:
        replying = self.state == "REPLY"
        return {"rx_ready": int(self.state == "RECEIVE"), "tx_valid": int(replying),
                "tx_payload": self.reply_byte() if replying else 0,
                "cyc": self.cyc, "stb": self.cyc, "we": self.we,
                "adr": self.addr & self.addr_mask, "dat_w": self.data, "sel": 0b1111,
                "checksum_error": self.checksum_error,
                "bus_timeout_error": self.bus_timeout_error}

    def step(self, rx_valid=0, rx_payload=0, tx_ready=0, ack=0, dat_r=0) -> dict:
        out = self.outputs()
        self.checksum_error = self.bus_timeout_error = 0
        if self.state == "RECEIVE":
            if rx_valid:
                byte = rx_payload
                self.timer = 0
                last = 7 if self.cmd == self.W else 3
                if self.count == 0:
                    if byte in (self.W, self.R):
                        self.cmd, self.total, self.data, self.count = byte, byte, 0, 1
                elif self.count == last:
                    self.count = 0
                    if (self.total + byte) & 0xFF == 0:
                        self.cyc, self.we = 1, int(self.cmd == self.W)
                        self.state = "BUS"
                    else:
                        self.status, self.total, self.index = self.E, 0, 0
                        self.checksum_error = 1
                        self.state = "REPLY"
                    return out
                elif self.count < 3:
                    self.total = (self.total + byte) & 0xFF
                    self.addr = ((self.addr << 8) | byte) & 0xFFFF
                    self.count += 1
                else:
                    self.total = (self.total + byte) & 0xFF
                    self.data = ((self.data << 8) | byte) & 0xFFFFFFFF
                    self.count += 1
            elif self.count:
                if self.timer == self.frame_timeout - 1:
                    self.count = self.timer = 0
                else:
                    self.timer += 1
        elif self.state == "BUS":
            if ack or self.timer == self.bus_timeout - 1:
                self.cyc, self.timer, self.total, self.index = 0, 0, 0, 0
                self.state = "REPLY"
                if ack:
                    self.status = self.cmd
                    if self.cmd == self.R:
                        self.data = dat_r
                else:
                    self.status, self.data, self.bus_timeout_error = self.T, 0, 1
            else:
                self.timer += 1
        elif tx_ready:                              # REPLY
            self.total = (self.total + out["tx_payload"]) & 0xFF
            self.index += 1
            if self.index == 8:
                self.index, self.total, self.timer, self.state = 0, 0, 0, "RECEIVE"
        return out


def _mask(width: int) -> int:
    return (1 << width) - 1


class RegisterBankModel:
    """:class:`demo.register_bank.RegisterBank`: ``step(cyc, stb, we, adr, dat_w,
    ro=..., sets=...)``; ``ro`` maps read-only names to this cycle's values, ``sets`` maps
    settable names to ``(set, value)``."""

    def __init__(self, window, init=None):
        self.window = window
        self.values = {r.name: (init or {}).get(r.name, 0) for r in window.regs
                       if r.access == "RW"}
        self.strobes = {r.name: 0 for r in window.regs if r.access == "W"}
        self.ack, self.dat_r = 0, 0

    def outputs(self) -> dict:
        return {"ack": self.ack, "dat_r": self.dat_r, **self.values, **self.strobes}

    def step(self, cyc=0, stb=0, we=0, adr=0, dat_w=0, ro=None, sets=None) -> dict:
        out = self.outputs()
        ro, sets = ro or {}, sets or {}
        request = cyc and stb and not self.ack
        for name in self.strobes:
            self.strobes[name] = 0
        written = None
        if request:
            reg = next((r for r in self.window.regs if r.offset == adr), None)
            if reg is None or reg.access == "W":
                self.dat_r = 0
            elif reg.access == "RW":
                self.dat_r = out[reg.name]
            else:
                self.dat_r = ro[reg.name] & _mask(reg.width)
            if reg is not None and we:
                if reg.access == "RW":
                    self.values[reg.name] = dat_w & _mask(reg.width)
                    written = reg.name
                elif reg.access == "W":
                    self.strobes[reg.name] = 1
        for name, (go, value) in sets.items():
            if go and name != written:
                self.values[name] = value
        self.ack = int(bool(request))
        return out


class ButtonsModel:
    """:class:`demo.buttons.Buttons`: ``step(raw)``."""

    def __init__(self, count: int, debounce: int):
        self.debounce = debounce
        self.s1 = self.s2 = self.state = self.pressed = self.prescaler = 0

    def outputs(self) -> dict:
        return {"state": self.state, "pressed": self.pressed}

    def step(self, raw: int = 0) -> dict:
        out = self.outputs()
        self.pressed = 0
        if self.prescaler == self.debounce - 1:
            self.prescaler = 0
            self.pressed = self.s2 & ~self.state
            self.state = self.s2
        else:
            self.prescaler += 1
        self.s1, self.s2 = raw, self.s1
        return out


class ArbiterModel:
    """:class:`demo.arbiter.WishboneArbiter`: ``outputs()`` is the bus side (registered),
    ``step(m0, m1, ack)`` takes each master's outputs of the cycle (dicts with ``cyc stb we adr
    dat_w sel``) and the slaves' ``ack``, and returns the owner of the cycle."""

    REQUEST = ("cyc", "stb", "we", "adr", "dat_w", "sel")

    def __init__(self):
        self.owner = 0
        self.bus = dict.fromkeys(self.REQUEST, 0)

    def outputs(self) -> dict:
        return dict(self.bus)

    def step(self, m0, m1, ack=0) -> int:
        owner = self.owner
        master = m1 if owner else m0
        if not (master["cyc"] or self.bus["cyc"]):
            if m1["cyc"]:
                self.owner = 1
            elif m0["cyc"]:
                self.owner = 0
        self.bus = {name: master[name] for name in self.REQUEST}
        self.bus["cyc"] = int(bool(master["cyc"] and not ack))
        self.bus["stb"] = int(bool(master["stb"] and not ack))
        return owner


class SequencerModel:
    """:class:`demo.bus_master.BusSequencer`:
    ``step(ack, dat_r, enable_toggle, fault_clear)``."""

    def __init__(self, init, ctrl_addr, enable_mask, clear_addr, clear_value, ctrl_width=32):
        self.init = list(init)
        self.ctrl_mask = (1 << ctrl_width) - 1
        self.ctrl_addr, self.enable_mask = ctrl_addr, enable_mask
        self.clear_addr, self.clear_value = clear_addr, clear_value
        self.state, self.index, self.toggle, self.clear, self.ctrl = "IDLE", 0, 0, 0, 0
        self.cyc = self.we = self.adr = self.dat_w = 0

    def outputs(self) -> dict:
        busy = self.index != len(self.init) if self.state == "IDLE" else True
        return {"cyc": self.cyc, "stb": self.cyc, "we": self.we, "adr": self.adr,
                "dat_w": self.dat_w, "sel": 0b1111, "busy": int(busy)}

    def _access(self, we, adr, dat=0):
        self.cyc, self.we, self.adr, self.dat_w = 1, we, adr, dat

    def step(self, ack=0, dat_r=0, enable_toggle=0, fault_clear=0) -> dict:
        out = self.outputs()
        taken_toggle = taken_clear = 0
        if self.state == "IDLE":
            if self.index != len(self.init):
                self._access(1, *self.init[self.index])
                self.index += 1
                self.state = "WRITE"
            elif self.toggle:
                taken_toggle = 1
                self._access(0, self.ctrl_addr)
                self.state = "READ_CTRL"
            elif self.clear:
                taken_clear = 1
                self._access(1, self.clear_addr, self.clear_value)
                self.state = "WRITE"
        elif self.state == "READ_CTRL":
            if ack:
                self.cyc, self.ctrl = 0, (dat_r & self.ctrl_mask) ^ self.enable_mask
                self.state = "WRITE_CTRL"
        elif self.state == "WRITE_CTRL":
            self._access(1, self.ctrl_addr, self.ctrl)
            self.state = "WRITE"
        elif ack:                                    # WRITE
            self.cyc, self.state = 0, "IDLE"
        self.toggle = int((self.toggle and not taken_toggle) or enable_toggle)
        self.clear = int((self.clear and not taken_clear) or fault_clear)
        return out


class DemoModel:
    """:class:`demo.design.DemoDesign`: ``step(uart_rx, buttons, fault_in)``
    returns the pins of this cycle, then advances every block one clock.

    Every signal between blocks is registered or combinational from registers (the decoder and
    the arbiter's ``ack`` routing are evaluated here), so each block's outputs of the cycle are
    taken first and then every block steps."""

    def __init__(self, config):
        from mdfqm_model.nco import NcoModel
        from mdfqm_model.top import TopModel
        from mdfqm_spec import regmap as top_map
        from mdfqm_spec.regmap import ID_VALUE, TOP_BASE, demo_window

        c = self.config = config
        self.n = n = c.phases
        self.urx, self.utx = UartRxModel(c.divider), UartTxModel(c.divider)
        self.bridge = BridgeModel(16, c.bus_timeout, c.frame_timeout)
        self.seq = SequencerModel(c.top_init, TOP_BASE + top_map.CTRL, top_map.CTRL_ENABLE,
                                  TOP_BASE + top_map.CMD, top_map.CMD_FAULT_CLEAR,
                                  top_map.TOP["CTRL"].width)
        self.arbiter = ArbiterModel()
        self.demo_window = demo_window(n, c.width, c.acc_bits)
        self.demo = RegisterBankModel(self.demo_window, c.demo_init)
        self.nco = NcoModel(n, c.width, c.acc_bits, c.table_bits, c.sample_width)
        self.top = TopModel(n, c.width, dead_min=c.dead_min, max_bits=c.max_bits)
        self.top_base, self.top_width = TOP_BASE, top_map.ADDR_WIDTH
        self.buttons = ButtonsModel(len(c.buttons), c.debounce) if c.buttons else None
        self.cycles = self.snap_cycles = 0
        self.led_active = 0
        self.answers = (False, False)       # the windows that held the address a clock ago
        self.constants = {"ID": ID_VALUE, "INFO": c.info, "CLK_HZ": c.clk_hz}

    def pins(self) -> dict:
        d = self.top.driver.outputs()
        return {"uart_tx": self.utx.tx, "upper": d["upper"], "lower": d["lower"],
                "led_active": self.led_active, "led_fault": d["fault"],
                "heartbeat": (self.cycles >> self.config.heartbeat_bit) & 1,
                "trigger": self.nco.acc >> (self.config.acc_bits - 1)}

    def step(self, uart_rx=1, buttons=0, fault_in=0) -> dict:
        c = self.config
        pins = self.pins()
        urx, br, utx = self.urx.outputs(), self.bridge.outputs(), self.utx.outputs()
        seq, owner, bus = self.seq.outputs(), self.arbiter.owner, self.arbiter.outputs()
        demo, nco = self.demo.outputs(), self.nco.outputs()
        btn = self.buttons.outputs() if self.buttons else {"state": 0, "pressed": 0}
        pressed = {a: (btn["pressed"] >> i) & 1 for i, a in enumerate(c.buttons)}

        # arbiter (its bus side registered) and decoder: the request routed by its address,
        # the answer by the window that held the address a clock before
        adr = bus["adr"]
        hit_top = adr >> self.top_width == self.top_base >> self.top_width
        dw = self.demo_window
        hit_demo = adr >> dw.addr_width == dw.base >> dw.addr_width
        answers_top, answers_demo = self.answers
        ack = int((self.top.front.ack and answers_top) or (demo["ack"] and answers_demo))
        dat_r = ((self.top.front.dat_r if answers_top else 0)
                 | (demo["dat_r"] if answers_demo else 0))
        self.answers = (hit_top, hit_demo)
        ref_ready = self.top.ref_ready

        self.urx.step(rx=uart_rx, ready=br["rx_ready"])
        self.bridge.step(rx_valid=urx["valid"], rx_payload=urx["payload"], tx_ready=utx["ready"],
                         ack=ack and not owner, dat_r=dat_r)
        self.utx.step(valid=br["tx_valid"], payload=br["tx_payload"])
        self.seq.step(ack=ack and owner, dat_r=dat_r, enable_toggle=pressed.get("enable", 0),
                      fault_clear=pressed.get("fault_clear", 0))
        self.arbiter.step(br, seq, ack)

        freq, amp = demo["NCO_FREQ"], demo["NCO_AMP"]
        freq_top, amp_top = _mask(c.acc_bits), _mask(c.width - 1)
        up, step = freq + (freq >> 3) + 1, c.amp_step
        sets = {
            "NCO_FREQ": (pressed.get("freq_up", 0) | pressed.get("freq_down", 0),
                         min(up, freq_top) if pressed.get("freq_up", 0)
                         else max(freq - (freq >> 3) - 1, 0)),
            "NCO_AMP": (pressed.get("amp_up", 0) | pressed.get("amp_down", 0),
                        min(amp + step, amp_top) if pressed.get("amp_up", 0)
                        else max(amp - step, 0)),
        }
        ro = dict(self.constants, NCO_PHASE=nco["phase"], CYCLES=self.snap_cycles,
                  BUTTONS=btn["state"])
        self.demo.step(cyc=bus["cyc"] and hit_demo, stb=bus["stb"] and hit_demo, we=bus["we"],
                       adr=adr & _mask(dw.addr_width), dat_w=bus["dat_w"], ro=ro, sets=sets)
        self.nco.step(freq=freq, amplitude=amp, ready=ref_ready)
        self.top.step(wb_cyc=int(bool(bus["cyc"] and hit_top)),
                      wb_stb=int(bool(bus["stb"] and hit_top)), wb_we=bus["we"],
                      wb_adr=adr & _mask(self.top_width), wb_dat_w=bus["dat_w"],
                      ref_valid=nco["valid"], ref=nco["payload"], fault_in=fault_in)

        upper, lower = pins["upper"], pins["lower"]
        if demo["SNAPSHOT"]:
            self.snap_cycles = self.cycles
        self.cycles = (self.cycles + 1) & 0xFFFFFFFF
        self.led_active = int((upper | lower) != 0)
        if self.buttons:
            self.buttons.step(raw=buttons)
        return pins
