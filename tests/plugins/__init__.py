"""Plug-ins defined in the tests only, each one module (the measured extensions of issue 34)."""
