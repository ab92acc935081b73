"""Rigidity of assembled furniture, measured in the environment with the welds the task makes.

`assemble` places every part of a furniture in its assembled pose standing on
the floor and joins them through the task's own connect (snap, weld, close
loops). `stand` then simulates with idle actions and measures how far each
part drifts and turns, and how much the assembly deforms (the largest change
of any part's pose relative to the root part), which separates bending of the
welds from settling of the whole on the floor.
"""

import dataclasses

import mujoco
import numpy as np

import ikea_suite
from ikea_suite import geometry
from ikea_suite.props import model_format

_GAP = 1e-4   # metres: the assembly starts this far above the floor


@dataclasses.dataclass(frozen=True)
class Motion:
  """Largest motion over the parts of an assembly during a simulated interval."""
  drift: float         # m, any part's displacement in the world
  turn: float          # rad, any part's rotation in the world
  deformation: float   # m, any point of a part's bounding box relative to the root part
  worst_part: str


def assemble(name, lift=0.0, **options):
  """An environment (cursor robot) whose furniture is fully connected in its assembled pose,
  its lowest point `lift` above the floor."""
  env = ikea_suite.load(name, "cursor", **options)
  env.reset()
  task, physics = env.task, env.physics
  spec = task.furniture.spec
  bottom = min(p.assembled_corners()[:, 2].min() for p in spec.parts)
  def place(height):
    for k, part_spec in enumerate(spec.parts):
      task.furniture.set_part_pose(physics, k, part_spec.pos + [0.0, 0.0, height],
                                   geometry.mat_to_quat(part_spec.rot))
    physics.forward()
  place(lift - bottom + _GAP)
  # The collision bounds' corners can lie below the lowest point of a collision mesh
  # (MuJoCo frames a mesh geom on its principal axes, and the bounds are that frame's
  # box): set such an assembly down onto what it stands on instead of dropping it.
  air = _floor_gap(physics, task.furniture) if not lift else _GAP
  if air > 2 * _GAP:
    place(lift - bottom + _GAP - (air - _GAP))
  table = task.furniture.connectors
  for pair in task.design_pairs:
    con_a, con_b = table.pair_a[pair], table.pair_b[pair]
    state = task.state
    if (state.connector_used[con_a] or state.connector_used[con_b]
        or state.same_group(table.part[con_a], table.part[con_b])):
      continue
    task.connect_in_place(physics, pair)
  return env


def _floor_gap(physics, furniture):
  """Metres between the floor and the nearest collision geom of the furniture (up to 5 cm)."""
  model, data = physics.model.ptr, physics.data.ptr
  floors = np.flatnonzero((model.geom_type == mujoco.mjtGeom.mjGEOM_PLANE) & (model.geom_bodyid == 0))
  geoms, _ = model_format.collision_geoms(model, furniture.body_ids)
  return min(mujoco.mj_geomDistance(model, data, int(f), int(g), 0.05, None)
             for f in floors for g in geoms)


def _relative(pos, rot, root):
  """Every part's pose in the root part's frame."""
  return np.einsum("ji,nj->ni", rot[root], pos - pos[root]), np.einsum("ji,njk->nik", rot[root], rot)


def measure(env, seconds, between_steps=None):
  """Simulates `env`'s physics for `seconds` (the robot idle, no task logic: a completed
  assembly would end the episode) and returns the Motion. `between_steps(step)`, if
  given, runs before each control step's worth of physics, e.g. to move a held part."""
  task, physics = env.task, env.physics
  spec, root = task.furniture.spec, task.root_part
  pos0, rot0 = (np.array(x) for x in task.furniture.part_poses(physics))
  rel_pos0, rel_rot0 = _relative(pos0, rot0, root)
  corners = [geometry.box_corners(*p.bounds) for p in spec.parts]
  deformation = np.zeros(len(spec.parts))
  substeps = int(round(env.control_timestep() / physics.timestep()))
  for step in range(int(round(seconds / env.control_timestep()))):
    if between_steps is not None:
      between_steps(step)
    physics.step(substeps)
    pos, rot = task.furniture.part_poses(physics)
    rel_pos, rel_rot = _relative(pos, rot, root)
    for k, box in enumerate(corners):
      moved = box @ rel_rot[k].T + rel_pos[k] - (box @ rel_rot0[k].T + rel_pos0[k])
      deformation[k] = max(deformation[k], np.linalg.norm(moved, axis=1).max())
  pos, rot = task.furniture.part_poses(physics)
  drift = np.linalg.norm(pos - pos0, axis=1)
  turn = np.array([np.linalg.norm(geometry.mat_to_axis_angle(r @ r0.T)) for r, r0 in zip(rot, rot0)])
  worst = int(np.argmax(deformation))
  return Motion(float(drift.max()), float(turn.max()), float(deformation.max()),
                spec.parts[worst].name)
