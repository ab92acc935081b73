"""An optional initial layout kept in a model's metadata, e.g. the original environment's.

A model may carry, in its `furniture` metadata text, one entry per part:
`initpos.<part>=x y z qw qx qy qz` (metres, unit quaternion, world frame):
where that part starts. Models converted by ikea-suite-import-original keep
the original environment's `<part>_initpos` layout this way. The task's own
placement (scattered parts) is unchanged; a user who wants this layout
applies it after reset:

    env = ikea_suite.load("my_models/table_lack_0825.xml", "cursor", seed=0)
    env.reset()
    with env.physics.reset_context():
      layout.apply_initial_layout(env.physics, env.task.furniture)
"""

import numpy as np

from ikea_suite import errors
from ikea_suite.props import furniture_spec

PREFIX = "initpos."


def initial_layout(
    spec: furniture_spec.FurnitureSpec) -> dict[str, tuple[np.ndarray, np.ndarray]]:
  """The layout in a model's metadata.

  Args:
    spec: a FurnitureSpec (model_format.load_spec).

  Returns:
    part name -> (position (3,), unit quaternion (4,)); empty when the model has none.

  Raises:
    ModelFormatError: an entry names no part or is not 7 finite numbers with a unit quaternion.
  """
  parts = {p.name for p in spec.parts}
  out = {}
  for key, value in spec.metadata.items():
    if not key.startswith(PREFIX):
      continue
    label = f"<text name='furniture'> {key}"
    part = key[len(PREFIX):]
    if part not in parts:
      raise errors.ModelFormatError(spec.path, label,
                                    f"names part {part!r}; parts are {sorted(parts)}")
    try:
      numbers = np.array([float(v) for v in value.split()])
    except ValueError:
      numbers = np.array([])
    if numbers.shape != (7,) or not np.all(np.isfinite(numbers)):
      raise errors.ModelFormatError(spec.path, label,
                                    f"{value!r} must be 7 numbers: x y z qw qx qy qz")
    if abs(np.linalg.norm(numbers[3:]) - 1.0) > 1e-4:
      raise errors.ModelFormatError(spec.path, label,
                                    f"quaternion {numbers[3:].tolist()} is not unit length")
    out[part] = (numbers[:3], numbers[3:])
  return out


def apply_initial_layout(physics, furniture) -> list[str]:
  """Puts every part that the layout names at its pose, at rest.

  Args:
    physics: the environment's physics (call inside `physics.reset_context()`).
    furniture: the environment's Furniture prop (`env.task.furniture`).

  Returns:
    The names of the parts placed.
  """
  layout = initial_layout(furniture.spec)
  placed = []
  for part, spec in zip(furniture.parts, furniture.spec.parts):
    if spec.name in layout:
      pos, quat = layout[spec.name]
      part.set_pose(physics, position=pos, quaternion=quat)
      part.set_velocity(physics, velocity=np.zeros(3), angular_velocity=np.zeros(3))
      placed.append(spec.name)
  return placed
