"""A slotted rack that holds thin panels upright, one per slot, as panels wait in a workshop.

A panel lying flat cannot be taken from above by a parallel gripper: it is
wider than the open fingers (a chair back at half scale is 200 mm across, the
grippers open 79-111 mm), and a flat wall taken across its height turns the
hand on its side when it is stood up, which puts the wrist in the floor. Stood
in a slot, the same panel is taken by its top edge, fingers across its
thickness, and is carried and lowered onto its mate already upright.

The rack is static: a base plate with a low fin either side of each slot. It
is built for the panels it holds (each slot is the panel's thickness plus
SLOT_PLAY wide and as long as the panel); the slots sit PITCH apart, so that
the open fingers of the widest-opening hand (the Jaco's, 111 mm) straddle one
panel clear of the next. The rack frame's x is along the row of slots; a
panel in slot k stands with its thickness along x, centred at `slot_centre(k)`.
"""

import numpy as np
from dm_control import composer
from dm_control import mjcf

PITCH = 0.11          # m between slot centres: 55 mm from a panel's middle to the next's
SLOT_PLAY = 0.002     # m of free play across a slot (1 mm a side of the panel)
# A round panel (a disc) stands on its rim: along its slot it is a wheel, and with nothing
# to stop it a round table top rolled out of the rack. Two chocks cradle it, their faces
# tangent to its rim CHOCK_ANGLE round from where it meets the plate, so that every
# contact pushes towards its centre (between box edges and the rim, MuJoCo's contacts
# did not, and a round top spun in place, 2 degrees a second).
CHOCK_ANGLE = np.radians(20.0)
CHOCK_LENGTH = 0.01   # m along the rim
CHOCK_DEPTH = 0.005   # m
PLATE = 0.008         # m, thickness of the base plate the panels stand on
FIN_THICKNESS = 0.005  # m
MARGIN = 0.01         # m the plate reaches beyond the slots and fins
# The fins reach 0.4 of the shortest panel's height, at most 30 mm, and leave its top
# FINGER_ROOM clear: low enough that the fingertips, which take a panel by its top 20 mm
# (experts/top_down_grasp.EDGE_GRIP), stay above them, high enough that a panel leans at most
# play / fin height (5 degrees for a 60 mm box wall) in its slot.
FIN_HEIGHT_FRACTION = 0.4
MAX_FIN_HEIGHT = 0.03
FINGER_ROOM = 0.025


class PanelRack(composer.Entity):
  """A static rack with one upright slot per panel.

  Args (to _build):
    slots: (thickness, length, height) of each panel, m, in slot order.
    discs: whether each panel is round (a disc: its slot gets chocks); default none.
    name: the model name.
  """

  def _build(self, slots, discs=None, name="panel_rack"):
    slots = np.asarray(slots, dtype=float).reshape(-1, 3)
    discs = [False] * len(slots) if discs is None else list(discs)
    self._mjcf_root = mjcf.RootElement(model=name)
    self._num_slots = len(slots)
    shortest = slots[:, 2].min()
    fin_height = min(MAX_FIN_HEIGHT, FIN_HEIGHT_FRACTION * shortest, shortest - FINGER_ROOM)
    self._fin_height = fin_height
    half_row = (self._num_slots - 1) * PITCH / 2 + PITCH / 2
    half_width = slots[:, 1].max() / 2 + MARGIN
    self._half_size = np.array([half_row, half_width])
    wood = self._mjcf_root.asset.add("material", name="rack_wood", rgba=(0.55, 0.42, 0.3, 1.0),
                                     specular=0.2, shininess=0.2)
    body = self._mjcf_root.worldbody
    upright = (1.0, 0.0, 0.0, 0.0)
    self._boxes = [((0.0, 0.0, PLATE / 2), (half_row, half_width, PLATE / 2), upright)]
    for k, (thickness, length, _) in enumerate(slots):
      for side in (-1, 1):
        x = self.slot_centre(k)[0] + side * (thickness + SLOT_PLAY + FIN_THICKNESS) / 2
        self._boxes.append(((x, 0.0, PLATE + fin_height / 2),
                            (FIN_THICKNESS / 2, length / 2 + MARGIN / 2, fin_height / 2),
                            upright))
    names = ["plate"] + [f"fin_{k}_{side}" for k in range(self._num_slots) for side in "ab"]
    for k, ((thickness, _, height), disc) in enumerate(zip(slots, discs)):
      if not disc:
        continue
      radius, angle = height / 2, CHOCK_ANGLE
      for side in (-1, 1):   # turned about x so that its top face is tangent to the rim
        touch = np.array([self.slot_centre(k)[0], side * radius * np.sin(angle),
                          PLATE + radius * (1 - np.cos(angle))])
        inward = np.array([0.0, -side * np.sin(angle), np.cos(angle)])
        self._boxes.append((tuple(touch - inward * CHOCK_DEPTH / 2),
                            ((thickness + SLOT_PLAY) / 2, CHOCK_LENGTH / 2, CHOCK_DEPTH / 2),
                            (np.cos(side * angle / 2), np.sin(side * angle / 2), 0.0, 0.0)))
        names.append(f"chock_{k}_{'ab'[side > 0]}")
    self._geoms = [body.add("geom", name=name, type="box", material=wood, pos=pos, size=size,
                            quat=quat)
                   for name, (pos, size, quat) in zip(names, self._boxes)]

  @property
  def mjcf_model(self):
    return self._mjcf_root

  @property
  def num_slots(self):
    return self._num_slots

  @property
  def half_size(self):
    """Half extents (2,) of the rack's footprint along its own x (the row) and y, m."""
    return self._half_size.copy()

  @property
  def fin_height(self):
    """Height (m) of the fins above the plate."""
    return self._fin_height

  @property
  def lean(self):
    """The most (rad) a panel standing in the middle of its slot leans before it meets a
    fin's top edge: the play either side of it over the fins' height."""
    return float(np.arctan2(SLOT_PLAY / 2, self._fin_height))

  @property
  def boxes(self):
    """[(centre (3,), half sizes (3,), quaternion (4,))] of the plate, the fins and any chocks,
    m, rack frame."""
    return [(np.array(pos), np.array(size), np.array(quat)) for pos, size, quat in self._boxes]

  @property
  def geoms(self):
    """The plate, the fins and any chocks: the rack's collision geoms, on which panels stand."""
    return list(self._geoms)

  def slot_centre(self, k):
    """Point (3,) in the rack frame where slot k's panel stands: the middle of its bottom edge."""
    return np.array([(k - (self._num_slots - 1) / 2) * PITCH, 0.0, PLATE])
