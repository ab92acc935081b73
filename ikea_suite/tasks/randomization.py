"""Domain randomization of physics and visuals, applied at the start of every episode."""

from ikea_suite import errors


class OptionValueError(errors.IkeaSuiteError, ValueError):
  """An option whose value is out of range or of the wrong form."""
