"""The progress bar of a sweep run: :class:`Progress`, on stderr."""

from __future__ import annotations

import sys
import time

__all__ = ["Progress"]


class Progress:
    """Progress bar on stderr: tqdm when it is installed, else a dependency-free one (one line
    per update when the stream is not a terminal)."""

    def __init__(self, stream=None, enabled: bool = True, width: int = 30, use_tqdm=None):
        self.stream = stream or sys.stderr
        self.enabled = enabled
        self.width = width
        self.tty = hasattr(self.stream, "isatty") and self.stream.isatty()
        self.use_tqdm = use_tqdm
        self.bar = None

    def start(self, total: int) -> None:
        self.total, self.done, self.t0 = max(total, 1), 0, time.monotonic()
        if not self.enabled:
            return
        if self.use_tqdm is not False:
            try:
                from tqdm import tqdm
            except ImportError:
                tqdm = None
            if tqdm is not None:
                self.bar = tqdm(total=total, unit="point", file=self.stream, leave=True)
                return
        self._draw("starting")

    def advance(self, n: int, label: str = "") -> None:
        self.done += n
        if self.bar is not None:
            self.bar.set_postfix_str(label, refresh=False)
            self.bar.update(n)
        else:
            self._draw(label)

    def finish(self) -> None:
        if self.bar is not None:
            self.bar.close()
        elif self.enabled and self.tty:
            self.stream.write("\n")
            self.stream.flush()

    def _draw(self, label: str) -> None:
        if not self.enabled:
            return
        frac = self.done / self.total
        fill = round(frac * self.width)
        bar = "#" * fill + "." * (self.width - fill)
        line = (
            f"[{bar}] {100 * frac:5.1f}% {self.done}/{self.total} points "
            f"{time.monotonic() - self.t0:6.1f} s  {label}"
        )
        if self.tty:
            self.stream.write("\r" + line[:110].ljust(110))
        else:
            self.stream.write(line + "\n")
        self.stream.flush()
