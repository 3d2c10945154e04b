"""Board folder: see top.py."""
