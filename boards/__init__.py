"""Board tops of the MDFQM demo: one sub-folder per board (pins, clocking, demo top).

    python -m boards.build --board icebreaker      # bitstream into build/boards/icebreaker/
    python -m tools.board_report                   # resource / Fmax table of every board

The shared demo design is :mod:`demo`; :mod:`boards.common` is the glue.
"""

from __future__ import annotations

import importlib

__all__ = ["BOARDS", "DEFAULT", "get"]

#: board name -> module holding its ``BOARD``
BOARDS = {
    "icebreaker": "boards.icebreaker.top",
    "hx8k": "boards.hx8k.top",
    "ulx3s": "boards.ulx3s.top",
    "orangecrab": "boards.orangecrab.top",
}
DEFAULT = "icebreaker"


def get(name: str):
    """The :class:`boards.common.Board` called ``name``."""
    if name not in BOARDS:
        raise ValueError(f"board must be one of {sorted(BOARDS)}, not {name!r}")
    return importlib.import_module(BOARDS[name]).BOARD
