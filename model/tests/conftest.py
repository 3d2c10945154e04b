"""Shared fixtures: a seeded random generator that prints its seed and honours ``SEED=``."""

import os
import sys
from pathlib import Path

import numpy as np
import pytest

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))


@pytest.fixture
def rng(request):
    """``numpy.random.Generator`` seeded from ``$SEED`` or fresh entropy; the seed is printed."""
    env = os.environ.get("SEED")
    seed = int(env) if env else int(np.random.SeedSequence().entropy % (1 << 32))
    print(f"\n[{request.node.name}] SEED={seed}")
    return np.random.default_rng(seed)
