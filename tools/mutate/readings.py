"""Why a surviving mutant survives, as read from its counterexample and the tests: mutation key
-> a sentence (the report prints it beside the survivor). Keys name source and kind, not cells,
so a reading stays with its mutant when the design is rebuilt; a key that no longer occurs is
simply not printed."""


__all__ = ["READINGS"]
READINGS: dict[str, str] = {}
