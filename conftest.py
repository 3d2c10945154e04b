"""Fixtures shared by every test folder: a seeded random generator that prints its seed and
honours ``SEED=``."""

import os

import numpy as np
import pytest


@pytest.fixture
def rng(request):
    """``numpy.random.Generator`` seeded from ``$SEED`` or fresh entropy; the seed is printed."""
    env = os.environ.get("SEED")
    seed = int(env) if env else int(np.random.SeedSequence().entropy % (1 << 32))
    print(f"\n[{request.node.name}] SEED={seed}")
    return np.random.default_rng(seed)
