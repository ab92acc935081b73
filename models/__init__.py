"""Furniture and robot assets; installed as the package ikea_suite.models."""
