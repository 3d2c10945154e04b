"""Command line of the board demo: ``mdfqm-host [--port P] COMMAND`` (``python -m mdfqm_host``).

Commands:
  ports                 list serial ports; mark those that answer as the demo
  info                  configuration and current settings
  set [options]         --freq HZ --amp VDC --modulation M [--bits B] --zero-policy P
                        --dead-time NS --min-pulse NS --update-rate HZ --osr N
                        --watchdog UPDATES --enable/--disable --clear-fault --clear-watchdog
  counters              one snapshot of the switching counters
  monitor               live switching frequencies and status (Ctrl-C ends)
  read ADDR             raw register read (word address, or a register name)
  write ADDR VALUE      raw register write

``--port auto`` (default) probes every serial port for the demo's ID; ``--port sim://`` talks
to :class:`~.simdevice.SimulatedDevice`.
"""

from __future__ import annotations

import argparse
import sys
import time

from .client import Client, NoReplyError
from .device import MODULATIONS, ZERO_POLICIES, DemoDevice, NotDemoError, linear_limit
from .simdevice import SimulatedDevice

__all__ = ["find_ports", "main", "open_port"]

#: USB IDs of the boards' UART bridges (FT2232H: iCEBreaker, HX8K; FT231X: ULX3S)
KNOWN_USB = {(0x0403, 0x6010): "FTDI FT2232H", (0x0403, 0x6015): "FTDI FT231X",
             (0x0403, 0x6001): "FTDI FT232R", (0x0403, 0x6014): "FTDI FT232H",
             (0x10C4, 0xEA60): "CP210x", (0x1A86, 0x7523): "CH340"}


def _serial():
    try:
        import serial
        import serial.tools.list_ports
    except ImportError as error:   # pragma: no cover - pyserial is a dependency of mdfqm-host
        raise SystemExit("pyserial is needed for real ports: pip install pyserial") from error
    return serial


def open_port(name: str, baud: int, timeout: float):
    """A serial-like port: a real one, or ``sim://`` for the simulated device."""
    if name.startswith("sim://"):
        return SimulatedDevice()
    serial = _serial()
    return serial.Serial(name, baudrate=baud, timeout=timeout)


def find_ports(baud: int, timeout: float, comports=None, opener=None) -> list[tuple]:
    """``(device, description, answers)`` for every serial port, known UART bridges first;
    ``answers`` is True when the port reads back the demo's ID. Only USB serial ports are
    probed (a request is written to them); built-in UARTs are listed, never written to."""
    if comports is None:
        comports = _serial().tools.list_ports.comports
    opener = opener or (lambda dev: open_port(dev, baud, timeout))
    found = []
    for port in comports():
        known = KNOWN_USB.get((port.vid, port.pid))
        answers = False
        if port.vid is None:
            found.append((port.device, port.description or "", False, False))
            continue
        try:
            handle = opener(port.device)
            try:
                DemoDevice(Client(handle, retries=0))
                answers = True
            finally:
                handle.close()
        except (OSError, NotDemoError, ValueError):
            answers = False
        found.append((port.device, known or port.description or "", answers, known is not None))
    found.sort(key=lambda f: (not f[2], not f[3], f[0]))
    return [(dev, desc, answers) for dev, desc, answers, _ in found]


def connect(args) -> DemoDevice:
    if args.port == "auto":
        for dev, _, answers in find_ports(args.baud, args.timeout):
            if answers:
                args.port = dev
                break
        else:
            raise SystemExit("no serial port answers as the MDFQM demo (try --port, or "
                             "`ports` to list them)")
    handle = open_port(args.port, args.baud, args.timeout)
    try:
        return DemoDevice(Client(handle, retries=args.retries))
    except (NoReplyError, NotDemoError) as error:
        raise SystemExit(f"{args.port}: {error}") from error


def _addr(text: str, device: DemoDevice) -> int:
    try:
        return int(text, 0)
    except ValueError:
        pass
    name = text.upper()
    for reg in device.demo.regs:
        if reg.name == name:
            return device.demo.base + reg.offset
    fields = {"CTRL": "ctrl", "PERIOD": "period", "OSR": "osr", "DEAD": "dead",
              "MIN_PULSE": "min_pulse", "STATUS": "status", "DEAD_MIN": "dead_min"}
    if name in fields:
        return getattr(device.map, fields[name])
    raise SystemExit(f"unknown register {text!r}")


def cmd_info(device: DemoDevice, args, out) -> None:
    i, s = device.info, device.status()
    flags = " ".join(name for name, on in s.flags.items() if on) or "-"
    print(f"MDFQM demo on {args.port}: {i.phases} phases, {i.width}-bit references, "
          f"clock {i.clk_hz / 1e6:g} MHz, modulator: {device.map.name}", file=out)
    print(f"  enabled    {'yes' if s.enabled else 'no'}    status: {flags}", file=out)
    print(f"  frequency  {s.freq_hz:.4f} Hz", file=out)
    print(f"  amplitude  {s.amplitude:.4f} Vdc (linear up to {linear_limit(i.phases):.3f})",
          file=out)
    built_in = ", ".join(MODULATIONS[:i.modes])
    bits = f" b = {s.bits} ({1 << s.bits} slots per update)" if s.bits else ""
    print(f"  modulation {s.modulation}{bits}; built in: {built_in} (max b {i.max_bits})",
          file=out)
    print(f"  zero policy {s.zero_policy} (MDFQM)", file=out)
    print(f"  updates    {s.update_hz / 1e3:.3f} kHz, OSR {s.osr}", file=out)
    print(f"  dead time  {s.dead_ns:.0f} ns, minimum pulse {s.min_pulse_ns:.0f} ns", file=out)
    if i.watchdog:
        watchdog = f"{s.watchdog} update starts" if s.watchdog else "off"
        print(f"  watchdog   {watchdog}, {s.watchdog_trips} trips", file=out)
    else:
        print("  watchdog   not built in", file=out)
    reactions = "all off, ASC low, ASC high" if i.asc else "all off"
    print(f"  fault reactions built in: {reactions}", file=out)


def cmd_set(device: DemoDevice, args, out) -> None:
    if args.freq is not None:
        print(f"frequency {device.set_frequency(args.freq):.4f} Hz", file=out)
    if args.amp is not None:
        print(f"amplitude {device.set_amplitude(args.amp):.4f} Vdc", file=out)
    if args.mode is not None:
        raise SystemExit("--mode is gone: the zero-state policy is --zero-policy "
                         f"({'/'.join(ZERO_POLICIES)}), the modulation mode --modulation "
                         f"({'/'.join(MODULATIONS)})")
    if args.bits is not None and args.modulation is None:
        raise SystemExit("--bits needs --modulation (a slot mode)")
    if args.modulation is not None:
        mode, bits = device.set_modulation(args.modulation, args.bits)
        print(f"modulation {mode}" + (f" b = {bits}" if bits else ""), file=out)
    if args.zero_policy is not None:
        device.set_zero_policy(args.zero_policy)
        print(f"zero policy {args.zero_policy}", file=out)
    if args.dead_time is not None:
        print(f"dead time {device.set_dead_time(args.dead_time):.0f} ns", file=out)
    if args.min_pulse is not None:
        device.set_min_pulse(args.min_pulse)
        print(f"minimum pulse {args.min_pulse:.0f} ns", file=out)
    if args.update_rate is not None:
        print(f"update rate {device.set_update_rate(args.update_rate) / 1e3:.3f} kHz",
              file=out)
    if args.osr is not None:
        device.set_osr(args.osr)
        print(f"OSR {args.osr}", file=out)
    if args.watchdog is not None:
        device.set_watchdog(args.watchdog)
        print(f"watchdog {args.watchdog or 'off'}", file=out)
    if args.clear_watchdog:
        device.clear_watchdog()
        print("watchdog cleared", file=out)
    if args.clear_fault:
        device.clear_fault()
        print("fault cleared", file=out)
    if args.enable is not None:
        device.enable(args.enable)
        print("enabled" if args.enable else "disabled", file=out)


def cmd_counters(device: DemoDevice, args, out) -> None:
    c = device.counters()
    print(f"cycles {c.cycles}", file=out)
    for i, s in enumerate(c.switches):
        print(f"leg {i}: {s} turn-ons", file=out)


def cmd_monitor(device: DemoDevice, args, out, sleep=time.sleep) -> None:
    clk = device.info.clk_hz
    earlier = device.counters()
    legs = " ".join(f"{'f_sw leg ' + str(i):>13}" for i in range(device.info.phases))
    print(f"{'time/s':>8} {legs} {'status':>16}", file=out)
    shown = 0
    live = out.isatty() if hasattr(out, "isatty") else False
    try:
        while args.count is None or shown < args.count:
            sleep(args.interval)
            now = device.counters()
            seconds, rates = now.rates(earlier, clk)
            status = device.status()
            flags = ",".join(n for n, on in status.flags.items() if on) or "-"
            line = (f"{seconds:8.3f} " + " ".join(f"{r / 1e3:10.3f} kHz" for r in rates)
                    + f" {flags:>16}")
            print(line, end="\r" if live else "\n", file=out, flush=True)
            earlier, shown = now, shown + 1
    except KeyboardInterrupt:
        pass
    if live:
        print(file=out)


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(prog="mdfqm-host",
                                     description="Control the MDFQM board demo over its UART.")
    parser.add_argument("--port", default="auto",
                        help="serial port, 'auto' (probe every port) or 'sim://' (default auto)")
    parser.add_argument("--baud", type=int, default=115200)
    parser.add_argument("--timeout", type=float, default=0.2, help="reply timeout in seconds")
    parser.add_argument("--retries", type=int, default=3)
    sub = parser.add_subparsers(dest="command", required=True)
    sub.add_parser("ports", help="list serial ports, mark the demo's")
    sub.add_parser("info", help="configuration and settings")
    s = sub.add_parser("set", help="change settings")
    s.add_argument("--freq", type=float, help="output frequency in Hz")
    s.add_argument("--amp", type=float, help="peak phase reference in Vdc")
    s.add_argument("--modulation", choices=MODULATIONS,
                   help="modulation mode (those the bitstream has: see info)")
    s.add_argument("--bits", type=int,
                   help="resolution b of a slot mode (2**b slots per update; default the largest)")
    s.add_argument("--zero-policy", choices=sorted(ZERO_POLICIES),
                   help="MDFQM's zero-state policy")
    s.add_argument("--mode", help=argparse.SUPPRESS)      # the old name: refused with a hint
    s.add_argument("--watchdog", type=int, metavar="UPDATES",
                   help="reference watchdog timeout in update starts (0: off)")
    s.add_argument("--clear-watchdog", action="store_true")
    s.add_argument("--dead-time", type=float, help="dead time in ns")
    s.add_argument("--min-pulse", type=float, help="minimum on-time in ns")
    s.add_argument("--update-rate", type=float, help="core updates per second")
    s.add_argument("--osr", type=int, help="updates per reference sample")
    s.add_argument("--clear-fault", action="store_true")
    g = s.add_mutually_exclusive_group()
    g.add_argument("--enable", dest="enable", action="store_true", default=None)
    g.add_argument("--disable", dest="enable", action="store_false")
    sub.add_parser("counters", help="one snapshot of the switching counters")
    mon = sub.add_parser("monitor", help="live switching frequencies")
    mon.add_argument("--interval", type=float, default=0.5)
    mon.add_argument("--count", type=int, default=None, help="stop after this many lines")
    r = sub.add_parser("read", help="raw register read")
    r.add_argument("addr")
    w = sub.add_parser("write", help="raw register write")
    w.add_argument("addr")
    w.add_argument("value")
    return parser


def main(argv=None, out=None) -> int:
    out = out or sys.stdout
    args = build_parser().parse_args(argv)
    if args.command == "ports":
        for dev, desc, answers in find_ports(args.baud, args.timeout):
            print(f"{dev:<24} {desc:<24} {'MDFQM demo' if answers else ''}", file=out)
        return 0
    device = connect(args)
    try:
        if args.command == "info":
            cmd_info(device, args, out)
        elif args.command == "set":
            cmd_set(device, args, out)
        elif args.command == "counters":
            cmd_counters(device, args, out)
        elif args.command == "monitor":
            cmd_monitor(device, args, out)
        elif args.command == "read":
            addr = _addr(args.addr, device)
            print(f"{addr:#06x}: {device.client.read(addr):#010x}", file=out)
        elif args.command == "write":
            addr = _addr(args.addr, device)
            device.client.write(addr, int(args.value, 0))
            print(f"{addr:#06x} <- {int(args.value, 0):#010x}", file=out)
    except (ValueError, OSError) as error:
        print(f"error: {error}", file=sys.stderr)
        return 1
    return 0

