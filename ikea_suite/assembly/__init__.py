"""The simulator-free core of assembly: which connectors mate, and in what order parts go in."""
