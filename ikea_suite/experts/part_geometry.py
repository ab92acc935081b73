"""Where the furniture's parts are and where they go, read from privileged state: part
poses, grasp points, assembled and mated poses, bounding corners, the assembly's
footprint, and the routes the Cursor oracle carries parts along. Shared by every expert;
nothing here moves."""

import numpy as np

from ikea_suite import geometry
from ikea_suite.tasks import panel_placement

_ARC_STEP = np.radians(30)


def part_pose(physics, furniture, part):
  body = furniture.body_ids[part]
  return physics.data.xpos[body].copy(), physics.data.xmat[body].reshape(3, 3).copy()


def grasp_point(physics, furniture, part):
  """World centre of the part's largest collision geom: a point a cursor can enclose."""
  model, data = physics.model, physics.data
  ids, owner = furniture.collision_geoms
  geoms = ids[owner == part]
  g = max(geoms, key=lambda g: np.prod(model.geom_aabb[g, 3:]))
  return data.geom_xpos[g] + data.geom_xmat[g].reshape(3, 3) @ model.geom_aabb[g, :3]


def across_long_axis(part_rot, bounds):
  """The horizontal unit vector across a part's long axis as it lies: the direction a
  top-down grasp closes the fingers along (any, for a rod standing on end). A panel's
  long axis is the one reaching furthest horizontally: standing in the rack, its width,
  never its height (a round seat standing on edge has two longest axes, and the vertical
  one left the fingers closing across its 179 mm face)."""
  extents = bounds[1] - bounds[0]
  if panel_placement.is_panel(extents):
    extents = extents * np.linalg.norm(part_rot[:2], axis=0)
  long_axis = part_rot[:, int(np.argmax(extents))].copy()
  long_axis[2] = 0.0
  if np.linalg.norm(long_axis) < 1e-6:
    long_axis = np.array([1.0, 0.0, 0.0])
  return np.cross([0.0, 0.0, 1.0], long_axis / np.linalg.norm(long_axis))


def design_to_world(physics, furniture, root):
  """The rigid map (rotation, translation) taking the design frame to where the root is now."""
  spec = furniture.spec.parts[root]
  pos, rot = part_pose(physics, furniture, root)
  rotation = rot @ spec.rot.T
  return rotation, pos - rotation @ spec.pos


def assembled_pose(physics, furniture, root, part):
  """World pose of `part` in its assembled place relative to the root part as it is now."""
  rotation, translation = design_to_world(physics, furniture, root)
  spec = furniture.spec.parts[part]
  return rotation @ spec.pos + translation, rotation @ spec.rot


def mated_part_pose(physics, furniture, pair, moving, twist):
  """Pose of `moving` that makes the connector pair's connectors coincide at `twist`, and
  the unit vector from the mating point to it (the side to approach from)."""
  table = furniture.connectors
  con_a, con_b = table.pair_a[pair], table.pair_b[pair]
  moving_con = con_a if table.part[con_a] == moving else con_b
  positions, rotations = furniture.part_poses(physics)
  cpos, crot = table.world_frames(positions, rotations)
  frame_pos, frame_rot = table.mated_frame(pair, moving_con, cpos, crot, twist)
  rot = frame_rot @ table.local_rot[moving_con].T
  pos = frame_pos - rot @ table.local_pos[moving_con]
  side = pos - frame_pos
  return pos, rot, side / max(np.linalg.norm(side), 1e-6)


def part_corners(furniture, part, pos, rot):
  """World corners (8, 3) of the part's collision bounds with the part at (pos, rot)."""
  return geometry.box_corners(*furniture.spec.parts[part].bounds) @ rot.T + pos


def parts_corners(physics, furniture, parts):
  """World corners (8 per part, stacked) of the parts' collision bounds as they lie now."""
  positions, rotations = furniture.part_poses(physics)
  return np.concatenate([part_corners(furniture, p, positions[p], rotations[p]) for p in parts])


def root_group(task):
  """Indices of the parts joined to the root (the root among them)."""
  labels = task.state.group_labels()
  return np.flatnonzero(labels == labels[task.root_part])


def nearer_another_rack(task, physics, part, point):
  """Whether `point` (world, xy used) lies nearer another panel rack than the one `part`
  stands in: with a two-arm robot's two racks, one each side
  (tasks/panel_placement.split_by_side), a mate on the other arm's side. Mates on its
  own side go first: a box wall from the left rack went to the far, right mate, and the
  right arm's wall then had to cross to the left one, out of reach. False with one rack
  or for a part in none."""
  groups = task.initializer.rack_groups
  mine = next((k for k, group in enumerate(groups) if part in group), None)
  if len(groups) < 2 or mine is None:
    return False
  centres = [physics.bind(rack.mjcf_model.worldbody).xpos[:2]
             for rack in task.initializer.fixtures]
  distances = [np.linalg.norm(np.asarray(point)[:2] - centre) for centre in centres]
  return bool(min(distances) < distances[mine])


def part_radius(furniture, part):
  """Radius of a sphere about the part's origin that holds all its collision geometry."""
  lo, hi = furniture.spec.parts[part].bounds
  return float(np.linalg.norm(np.maximum(np.abs(lo), np.abs(hi))))


def assembly_circle(physics, furniture, root):
  """Centre (x, y) and radius of the assembled furniture's footprint, where it is now."""
  rotation, translation = design_to_world(physics, furniture, root)
  corners = []
  for p in furniture.spec.parts:
    corners.append(p.assembled_corners() @ rotation.T + translation)
  corners = np.concatenate(corners)[:, :2]
  centre = (corners.min(0) + corners.max(0)) / 2
  return centre, float(np.linalg.norm(corners - centre, axis=1).max())


def route(start, entry, centre, radius, height):
  """Travel points from `start` to above-or-beside `entry` without crossing the circle.

  Out radially to `radius` at `height`, round the circle in steps of at most
  30 degrees, to the radius of the entry direction, down or up to the entry
  height there, then straight in to `entry`.
  """
  def polar(point):
    offset = point[:2] - centre
    return np.arctan2(offset[1], offset[0]), np.linalg.norm(offset)
  angle0, r0 = polar(start)
  angle1, r1 = polar(entry)
  r = max(radius, r0)
  sweep = (angle1 - angle0 + np.pi) % (2 * np.pi) - np.pi
  count = int(np.ceil(abs(sweep) / _ARC_STEP))
  points = [np.array([*(centre + r * _unit(angle0)), height])]
  for k in range(1, count + 1):
    points.append(np.array([*(centre + r * _unit(angle0 + sweep * k / count)), height]))
  outer = max(radius, r1)
  points.append(np.array([*(centre + outer * _unit(angle1)), height]))
  points.append(np.array([*(centre + outer * _unit(angle1)), entry[2]]))
  points.append(np.asarray(entry, float))
  return points


def _unit(angle):
  return np.array([np.cos(angle), np.sin(angle)])


def preferred_connector(physics, furniture, part, joined):
  """The connector of `part` to connect by, among those that meet a part in `joined` when
  assembled: one on the root-most, stiffest partner (largest smallest principal inertia,
  since a weld to a thin strip is soft about the strip's axis), nearest the part's centre.
  Returns (position, up axis) in the part's frame, the connector's name, and the
  partner part's index.
  """
  spec = furniture.spec
  index = {p.name: i for i, p in enumerate(spec.parts)}
  inertia = physics.model.body_inertia[furniture.body_ids]
  best = None
  for a, b in spec.assembled_connector_pairs():
    for c, m in ((spec.connectors[a], spec.connectors[b]), (spec.connectors[b], spec.connectors[a])):
      other = index[m.part]
      if index[c.part] == part and other in joined:
        key = (-inertia[other].min(), float(np.linalg.norm(c.pos)))
        if best is None or key < best[0]:
          best = (key, c, other)
  if best is None:
    return None
  return (best[1].pos, best[1].rot[:, 2]), best[1].name, best[2]


def tilt_about(pos, rot, pivot_local, axis_local, angle):
  """The pose (pos, rot) turned by `angle` about an axis through a point fixed to the part."""
  pivot = pos + rot @ pivot_local
  turn = geometry.axis_angle_to_mat(rot @ axis_local * angle)
  return pivot + turn @ (pos - pivot), turn @ rot
