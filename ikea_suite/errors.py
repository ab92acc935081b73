"""The package's one exception family: every error a user can cause is an IkeaSuiteError."""

import difflib


class IkeaSuiteError(Exception):
  """Base class of every error raised by ikea_suite for bad input."""


class UnknownNameError(IkeaSuiteError, KeyError):
  """A furniture, robot or option name that is not registered."""

  def __init__(self, kind, name, valid):
    self.kind, self.name, self.valid = kind, name, sorted(valid)
    close = difflib.get_close_matches(str(name), self.valid, n=3)
    hint = f" (did you mean {', '.join(close)}?)" if close else ""
    super().__init__(
        f"unknown {kind} {name!r}{hint}; valid {kind} names: {', '.join(self.valid)}")

  def __str__(self):  # KeyError would otherwise quote the whole message.
    return self.args[0]


class ModelFormatError(IkeaSuiteError, ValueError):
  """A furniture model file that breaks the format; names file, element and fault."""

  def __init__(self, path, element, problem):
    self.path, self.element, self.problem = str(path), element, problem
    super().__init__(f"{self.path}: {element}: {problem}")


class ConversionError(ModelFormatError):
  """A model in the original IKEA environment's format that cannot be converted; names the
  file, the element (a site, a body, a mesh) and why."""


class ImportSpecError(IkeaSuiteError, ValueError):
  """A furniture spec or mesh given to design.import_model that cannot be built."""


class ActionError(IkeaSuiteError, ValueError):
  """An action of the wrong shape or with non-finite entries."""


class OptionValueError(IkeaSuiteError, ValueError):
  """An option of load() with a value outside its valid range or choices."""


class UnsupportedPairError(IkeaSuiteError, ValueError):
  """A furniture, or a scale, that a robot's scripted expert is not measured to assemble;
  names the furniture it assembles and at what scale."""


class EpisodeStartError(IkeaSuiteError, RuntimeError):
  """An episode that could not start: its parts could not be laid out, or its first state
  is not a valid physics state; names the reason."""


class SequenceError(IkeaSuiteError, ValueError):
  """A furniture for which no assembly order with free insertion paths was found."""


class RenderAfterForkError(IkeaSuiteError, RuntimeError):
  """A process forked after its parent made an OpenGL context tried to render: the GL
  driver's state it inherited cannot make a new context (it would wait forever)."""
