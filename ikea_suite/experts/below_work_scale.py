"""What a scripted arm does differently with furniture built smaller than its robot's
work scale (experts/work_scale.py): parts a few centimetres long, mated a few centimetres
above the floor.

A part taken lying flat and turned upright to its mate turns the tool horizontal, at
the height of the grasp point. Held at its middle, a 92 mm bench end (bench_plank_pine
at scale 0.22) put the Sawyer's tool 65 mm above the floor, where its wrist (right_l6)
lay on the floor: the arm stopped 6.5-8 mm short of the mate while its task-space
target ran 27 mm below it, and the 4.4 mm connect distance was never met. Held near the
end away from its connectors, the hand stays that much higher.

Everything here applies only below the work scale (`active`), so episodes at the work
scale, on which the supported lists rest, do not depend on it.
"""

import numpy as np

# Fingertips' height (m) over the floor when closing on a part lying there (3 mm at the
# work scale): a 4-7 mm thick part gripped over its top 1-4 mm slid out of the tips as
# the tool turned it upright.
TIP_CLEARANCE = 0.001
# Room (m) left between the grasp point and the part's end for the pads to cover.
PAD_ROOM = 0.02


def active(env):
  """True for furniture built smaller than the robot's work scale."""
  return env.task.furniture.scale < env.task.robot.CONFIG.WORK_SCALE - 1e-9


def grip_shift(furniture, part):
  """Offset (m, part frame) of the grasp point from the part's centre: along its long
  axis, away from its connectors' mean position, as far as the pads leave room for.
  Zero for a part whose connectors lie symmetrically about its middle (a stretcher
  joined at both ends stays horizontal, tool down)."""
  bounds = furniture.spec.parts[part].bounds
  axis = int(np.argmax(bounds[1] - bounds[0]))
  table = furniture.connectors
  mean = table.local_pos[table.part == part].mean(axis=0)[axis]
  half = 0.5 * (bounds[1][axis] - bounds[0][axis])
  centre = 0.5 * (bounds[1][axis] + bounds[0][axis])
  shift = np.zeros(3)
  if abs(mean - centre) < 0.25 * half:
    return shift
  shift[axis] = centre - np.sign(mean - centre) * max(0.0, half - PAD_ROOM)
  return shift
