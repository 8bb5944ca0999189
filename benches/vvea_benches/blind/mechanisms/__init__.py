"""Mechanisms outside the diagnosis catalogue, one module each (physics, states, ranges in its docstring)."""
