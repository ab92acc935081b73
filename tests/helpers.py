"""Small helpers shared by tests: placing parts in their assembled pose, welds that are on."""

import mujoco
import numpy as np

from ikea_suite import geometry

LIFT = np.array([0.0, 0.0, 0.5])


def place_assembled(env, parts, offset=LIFT, extra_rot=None, extra_pos=None):
  """Puts `parts` (indices) at their assembled pose, raised by `offset`."""
  physics, furniture = env.physics, env.task.furniture
  for index in parts:
    spec = furniture.spec.parts[index]
    rot, pos = spec.rot, spec.pos + offset
    if extra_rot is not None and extra_rot.get(index) is not None:
      rot = extra_rot[index] @ rot
    if extra_pos is not None and extra_pos.get(index) is not None:
      pos = pos + extra_pos[index]
    furniture.parts[index].set_pose(physics, position=pos, quaternion=geometry.mat_to_quat(rot))
    furniture.parts[index].set_velocity(physics, velocity=np.zeros(3), angular_velocity=np.zeros(3))
  physics.forward()


def assembled_shape_error(env):
  """Largest distance (m) between the parts' centres and the design's, in the root part's frame.

  Parts are matched to the nearest design centre both ways, so interchangeable
  parts (legs in each other's corners) count as in place.
  """
  task = env.task
  root, spec = task.root_part, task.furniture.spec
  pos, rot = task.furniture.part_poses(env.physics)
  got = (pos - pos[root]) @ rot[root]
  design = np.array([p.pos for p in spec.parts])
  want = (design - design[root]) @ spec.parts[root].rot
  gaps = np.linalg.norm(got[:, None] - want[None], axis=2)
  return max(gaps.min(axis=0).max(), gaps.min(axis=1).max())


def part_index(env, name):
  return env.task.furniture.spec.part_index(name)


def connect_action(env):
  action = np.zeros(env.action_spec().shape)
  action[-1] = 1.0
  return action


def idle_action(env):
  return np.zeros(env.action_spec().shape)


def expert_steps(env):
  """Runs `env`'s scripted expert from reset, yielding the expert after each step, until
  the furniture is complete or time is up."""
  from ikea_suite import experts
  expert = experts.make_expert(env)
  timestep = env.reset()
  expert.reset()
  while not timestep.last() and not env.task.state.complete:
    timestep = env.step(expert(timestep))
    yield expert


def run_expert(env):
  """Runs `env`'s scripted expert from reset until the furniture is complete or time is up."""
  for _ in expert_steps(env):
    pass


def geoms_collide(physics, geom_a, geom_b):
  """MuJoCo's contype/conaffinity filter for two geoms."""
  m = physics.model
  return bool((m.geom_contype[geom_a] & m.geom_conaffinity[geom_b])
              or (m.geom_contype[geom_b] & m.geom_conaffinity[geom_a]))


def first_geom(env, part):
  """The part's first collision geom (visual-only geoms never collide)."""
  model = env.physics.model
  body = env.task.furniture.body_ids[part]
  return int(np.flatnonzero((model.geom_bodyid == body) & (model.geom_conaffinity != 0))[0])


def welds_on(physics):
  """Per equality constraint, whether it is a weld that is on (the grippers' finger
  couplings are joint equalities, always on, and hold no part)."""
  return physics.data.eq_active & (physics.model.eq_type == mujoco.mjtEq.mjEQ_WELD)
