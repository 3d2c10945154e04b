"""Stimulus as the specification's rules: small named sequences, each checking one promise of
the documents, composed by a run's scheduler with random background traffic.

A :class:`Sequence` names what it checks in ``rules``: a row of docs/robustness.md
(:func:`robustness`), a field or a clamp of the register map's source (:func:`rdl`,
spec/rdl/mdfqm_top.rdl), a section of docs/top.md or docs/contract.md (:func:`doc`). Its
``coverpoints`` are the bins it aims at; the run hits them from what the golden model shows.
Its ``body`` is a generator that yields once per clock, so a sequence reads top to bottom as
the firmware or the plant would act: write this, wait for that moment, raise that pin.
``claims`` names the resources it holds while it runs (the scheduler starts a sequence only
when none of them is held), so that two sequences never fight over one setting.

Each family of sequences (the top's, the generator's) is a subclass of :class:`Sequence`
with its own ``registry``; tb/test_spec_trace.py checks that every robustness row and every
register field and clamp is named by some sequence of some family.
"""

from __future__ import annotations

import re
from collections.abc import Iterator
from typing import ClassVar

#: the documents a rule can name
ROBUSTNESS = "docs/robustness.md"
RDL = "rdl"


def robustness(row: str) -> str:
    """The rule of a row of docs/robustness.md, named by the start of its first cell (without
    the backticks)."""
    return f"{ROBUSTNESS}: {row}"


def rdl(field: str, clamp: bool = False) -> str:
    """The rule of a register field of spec/rdl/mdfqm_top.rdl, ``"REG.FIELD"`` (an array
    register without its index), or of that field's clamp."""
    return f"{RDL}: {field}" + (" (clamp)" if clamp else "")


def doc(path: str, heading: str) -> str:
    """The rule of a section of a document: ``docs/top.md#<the heading's anchor>``."""
    return f"{path}#{anchor(heading)}"


def anchor(heading: str) -> str:
    """A heading's anchor as GitHub makes it: lower case, punctuation dropped, spaces to
    hyphens."""
    text = re.sub(r"[^\w\- ]", "", heading.strip().lower())
    return text.replace(" ", "-")


class Waits:
    """What a run offers its sequences to wait with (each yields once per clock)."""

    def wait(self, clocks: int):
        for _ in range(clocks):
            yield

    def until(self, predicate, limit: int):
        """Wait until ``predicate()`` holds (True) or ``limit`` clocks have passed (False)."""
        for _ in range(limit):
            if predicate():
                return True
            yield
        return False


class Sequence:
    """One named sequence of stimulus (see the module docstring).

    Subclasses set ``rules`` (the first the one it is named after), ``claims``, ``weight`` (how
    often the scheduler picks it among those with open bins, and in background traffic),
    ``closed_weight`` (the same once its bins are all hit, if not ``weight``) and implement
    :meth:`coverpoints` and :meth:`body`. ``run`` is the run it acts in."""

    #: the family's sequences, in definition order (each family's base class has its own)
    registry: ClassVar[list]
    #: the family's name ("top", "generator"), set by its base class
    family: ClassVar[str] = ""
    rules: ClassVar[tuple[str, ...]] = ()
    claims: ClassVar[frozenset] = frozenset()
    weight: ClassVar[float] = 1.0
    closed_weight: ClassVar[float | None] = None

    def __init_subclass__(cls, family: bool = False, **kwargs):
        super().__init_subclass__(**kwargs)
        if family:
            cls.registry = []
        elif cls.rules:
            cls.registry.append(cls)

    def __init__(self, run) -> None:
        self.run = run
        self.rng = run.rng

    @classmethod
    def applies(cls, run) -> bool:
        """Whether the sequence means anything in ``run`` (its configuration and length)."""
        return True

    @classmethod
    def coverpoints(cls, run) -> dict[str, tuple]:
        """The coverpoints the sequence aims at in ``run``: name -> the bins to hit."""
        return {}

    def body(self) -> Iterator[None]:
        """The stimulus, one ``yield`` per clock."""
        raise NotImplementedError

    @classmethod
    def key(cls) -> str:
        """The sequence's name in its family (two families may each have a ``SyncPulses``)."""
        return f"{cls.family}: {cls.__name__}"

    @classmethod
    def describe(cls) -> str:
        """The first sentence of the docstring: what the sequence does."""
        text = " ".join((cls.__doc__ or cls.__name__).split())
        return re.split(r"(?<=[\w)`]\.)\s", text, maxsplit=1)[0]


def every_rule(families) -> dict[str, list[type]]:
    """rule -> the sequences (of ``families``' registries) that name it."""
    rules: dict[str, list[type]] = {}
    for family in families:
        for sequence in family.registry:
            for rule in sequence.rules:
                rules.setdefault(rule, []).append(sequence)
    return rules
