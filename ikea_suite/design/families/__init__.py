"""Parametric furniture families; each module turns a few dimensions into a Blueprint."""
