"""A work-table arena: a rigid table in front of the robot, which stands on a pedestal as high.

The table top is 0.75 m high, 1.0 m deep and 1.6 m wide, 30 mm thick, on four
50 mm square legs: a common desk and lab-bench height (office desks stand
0.72-0.76 m) and a 160 x 100 cm bench top. The robot's base is mounted
at the height of the top, on a 0.4 m square pedestal that abuts the table's
back edge, the way a Panda or Jaco is clamped to a bench and a Sawyer's
pedestal is set to the bench's height. So the arm meets the table top exactly
as it meets the floor in the floor arena (same reach, same workspace box in its
base frame), and every part it can reach lies on the top: the top reaches
from 0.2 m to 1.2 m in front of the base (the arms' part reach is 0.8-0.95 m)
and 0.8 m to either side. It is deeper than an 80 cm desk because the scripted
arm sometimes pushes the growing assembly out past its reach: on a top ending
1.0 m out, such assemblies tipped over the front edge or fell off it in 3 of 6
Sawyer episodes (development seeds 0-5); 1.2 m out they stay on the top.

Cameras keep the floor arena's views, moved to look at the table top's centre.
Everything here is static world geometry (no bodies), like the floor. The top is a box,
which parts touch through MuJoCo's general convex collider rather than the floor's exact
plane colliders, so the scene tightens that collider's tolerance
(physics_settings.BOX_SUPPORT_CCD_TOLERANCE: at the default a round leg lying on the top
rolled over); parts then rest on the top as on the floor.
"""

import numpy as np

from ikea_suite import geometry
from ikea_suite import physics_settings
from ikea_suite.arenas import floor
from ikea_suite.arenas import support as support_lib

TABLE_HEIGHT = 0.75              # m, floor to the top surface
TABLE_SIZE = (1.0, 1.6)          # m, depth (along the robot's heading) x width
TOP_THICKNESS = 0.03             # m
LEG_WIDTH = 0.05                 # m, square legs
LEG_INSET = 0.05                 # m from the top's edges to the legs' centres
PEDESTAL_HALF = 0.2              # m, half the pedestal's square side; the table starts there
# Same friction as the floor, so the floor and table arenas differ only in geometry.
TOP_FRICTION = (0.9, 0.005, 0.0001)


class WorkTableArena(floor.FloorArena):
  """The floor arena plus a work table in front of a robot base and the pedestal it stands on.

  Args (to _build):
    base_xy: world xy (2,) of the robot base the table stands in front of (m).
    base_yaw: the robot's heading (rad); the table lies along it.
    height: table top height (m); the pedestal is as high.
    size: (depth, width) of the top (m).
  """

  def _build(self, name="work_table", base_xy=(-0.55, 0.0), base_yaw=0.0, height=TABLE_HEIGHT,
             size=TABLE_SIZE, floor_size=(4.0, 4.0)):
    super()._build(name=name, size=floor_size)
    root = self._mjcf_root
    physics_settings.configure_box_support(root)
    rot = geometry.rot_z(base_yaw)
    heading = rot[:2, 0]
    base_xy = np.asarray(base_xy, dtype=float)
    centre = base_xy + heading * (PEDESTAL_HALF + size[0] / 2)
    quat = geometry.mat_to_quat(rot)
    wood = root.asset.add("material", name="table_top", rgba=(0.72, 0.58, 0.42, 1.0),
                          specular=0.2, shininess=0.3, reflectance=0.02)
    steel = root.asset.add("material", name="table_steel", rgba=(0.45, 0.46, 0.48, 1.0),
                           specular=0.4, shininess=0.5)
    self._top = root.worldbody.add(
        "geom", name="table_top", type="box", material=wood, friction=TOP_FRICTION, quat=quat,
        pos=(*centre, height - TOP_THICKNESS / 2),
        size=(size[0] / 2, size[1] / 2, TOP_THICKNESS / 2))
    leg_height = height - TOP_THICKNESS
    for i, (sx, sy) in enumerate(((1, 1), (1, -1), (-1, 1), (-1, -1))):
      local = np.array([sx * (size[0] / 2 - LEG_INSET), sy * (size[1] / 2 - LEG_INSET)])
      xy = centre + rot[:2, :2] @ local
      root.worldbody.add("geom", name=f"table_leg_{i}", type="box", material=steel, quat=quat,
                         pos=(*xy, leg_height / 2),
                         size=(LEG_WIDTH / 2, LEG_WIDTH / 2, leg_height / 2))
    self._pedestal = root.worldbody.add(
        "geom", name="pedestal", type="box", material=steel, quat=quat,
        pos=(*base_xy, height / 2), size=(PEDESTAL_HALF, PEDESTAL_HALF, height / 2))
    self._support = support_lib.Support(height=float(height), centre=tuple(centre),
                                        yaw=float(base_yaw),
                                        half_size=(size[0] / 2, size[1] / 2))
    # Look at the table top as the floor arena's cameras look at the origin.
    shift = self._support.origin
    for camera_name, (pos, target) in floor.CAMERAS.items():
      camera = self._cameras[camera_name]
      camera.pos = np.add(pos, shift)
      camera.target.pos = np.add(target, shift)

  @property
  def support(self):
    """The table top (support.Support): where parts lie at the start of an episode."""
    return self._support

  @property
  def mount_height(self):
    """Height (m) the robot's base is raised by: the top of its pedestal."""
    return self._support.height

  @property
  def support_geoms(self):
    """Geoms parts rest on: the table top, and the floor for parts that fall off it."""
    return [self._floor, self._top]

  @property
  def table_top(self):
    return self._top
