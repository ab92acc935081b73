"""Converter from the original IKEA Furniture Assembly Environment's model format to ours.

reader reads an original MJCF file (repairing known quirks), names parses its
connector site names, assemble matches connector sites and solves the
assembled pose, convert writes a model in our format, and cli is the
`ikea-suite-import-original` command.
"""
