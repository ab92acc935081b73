"""The assembly task: connect every part of a furniture into one rigid assembly."""

import numpy as np
from dm_control import composer
from dm_env import specs
from dm_control.composer.observation import observable

from ikea_suite import geometry
from ikea_suite.tasks import alignment
from ikea_suite.tasks import assembly_state
from ikea_suite.tasks import collision_groups
from ikea_suite.tasks import placement
from ikea_suite.tasks import planner
from ikea_suite.tasks import rewards
from ikea_suite.tasks import welds

CONNECT_ACTION = "connect"


class Assembly(composer.Task):
  """Long-horizon furniture assembly (Lee et al. 2019) as a composer task.

  The action is the robot's actions followed by `connect`. When `connect` is
  on (> 0) the task checks every free mating connector pair between different
  assembled groups; the best-aligned attachable pair is snapped together
  (the smaller group moves), welded, and its groups stop colliding.

  Reward: `connection_reward` for each new connection plus `completion_bonus`
  when the last part joins, which also ends the episode (discount 0).
  With `reward="dense"`, staged shaping instead (tasks/rewards.py).
  """

  def __init__(self, arena, furniture, robot, thresholds=alignment.Thresholds(),
               control_timestep=0.05, physics_timestep=0.002, connection_reward=1.0,
               completion_bonus=10.0, initializer=None, reward="sparse"):
    self._arena, self._furniture, self._robot = arena, furniture, robot
    self._thresholds = thresholds
    self._connection_reward, self._completion_bonus = connection_reward, completion_bonus
    furniture.attach_to(arena)
    robot.mount(arena)
    self._table = furniture.connectors
    self._state = assembly_state.AssemblyState(len(furniture.parts), len(self._table))
    self._welds = welds.PartWelds(arena, furniture)
    self._collisions = collision_groups.CollisionGroups(len(furniture.parts))
    self._root = planner.root_part(furniture.spec)
    self.set_timesteps(control_timestep=control_timestep, physics_timestep=physics_timestep)
    robot.bind_scene(arena, furniture, self._state, self.control_timestep)
    initializer = initializer or placement.ScatteredParts(furniture)
    if hasattr(robot, "part_initializer"):   # a fixed-base arm keeps parts within its reach
      initializer = robot.part_initializer(furniture, initializer)
    self._initializer = initializer
    self._step_reward = 0.0
    self._blocked = ()
    self._suggestion_key = None
    self._dense = rewards.make(reward, self, connection_reward, completion_bonus)  # None: sparse
    self._task_observables = {
        "connections": observable.Generic(lambda physics: self._state.adjacency.copy()),
        "connectors_used": observable.Generic(
            lambda physics: self._state.connector_used.astype(np.float64)),
        "next_pair": observable.Generic(lambda physics: self.suggested_parts().astype(np.float64)),
    }
    for obs in self._task_observables.values():
      obs.enabled = True
    for entity in (furniture, robot):
      for obs in entity.observables.as_dict().values():
        obs.enabled = True

  # -- composer.Task interface -------------------------------------------------

  @property
  def root_entity(self):
    return self._arena

  @property
  def task_observables(self):
    return self._task_observables

  @property
  def action_names(self):
    return list(self._robot.action_names) + [CONNECT_ACTION]

  def action_spec(self, physics):
    names = self.action_names
    return specs.BoundedArray(shape=(len(names),), dtype=np.float64, minimum=-1.0, maximum=1.0,
                              name="\t".join(names))

  def after_compile(self, physics, random_state):
    # composer calls the task's hook before the entities'; the task needs part ids now.
    self._furniture.after_compile(physics, random_state)
    self._welds.after_compile(physics)
    self._collisions.after_compile(physics, self._furniture.body_ids)

  def initialize_episode(self, physics, random_state):
    self._state.reset()
    self._suggestion_key = None
    self._welds.reset(physics)
    self._collisions.reset(physics)
    self._initializer(physics, random_state)
    # Curriculum initializers leave connector pairs they placed assembled.
    for pair in getattr(self._initializer, "preassembled_pairs", ()):
      self.connect_in_place(physics, pair)
    self._step_reward = 0.0
    if self._dense is not None:
      self._dense.reset(physics)

  def before_step(self, physics, action, random_state):
    self._step_reward = 0.0
    self._blocked = ()
    self._robot.apply_action(physics, action[:-1], random_state)
    if action[-1] > 0 and self.try_connect(physics):
      self._step_reward += self._connection_reward
      if self._state.complete:
        self._step_reward += self._completion_bonus

  def get_reward(self, physics):
    return self._step_reward if self._dense is None else self._dense.reward(physics)

  def should_terminate_episode(self, physics):
    return self._state.complete

  def get_discount(self, physics):
    return 0.0 if self._state.complete else 1.0

  # -- assembly ------------------------------------------------------------------

  @property
  def furniture(self):
    return self._furniture

  @property
  def robot(self):
    return self._robot

  @property
  def arena(self):
    return self._arena

  @property
  def state(self):
    return self._state

  @property
  def thresholds(self):
    return self._thresholds

  @property
  def blocked_connections(self):
    """Why `connect` made no connection on the last step: one message per refused pair."""
    return self._blocked

  @property
  def dense_reward(self):
    """The `rewards.DenseReward` in use, or None with the sparse reward."""
    return self._dense

  @property
  def root_part(self):
    return self._root

  def suggested_parts(self):
    """[moving part, target part] of the planner's next connection, or [-1, -1]."""
    made = len(self._state.connections)
    if self._suggestion_key != made:  # the plan changes only when a connection is made
      suggestion = planner.next_pair(self._table, self._state, self._root)
      self._suggestion = np.array([-1, -1]) if suggestion is None else np.array(suggestion[1:])
      self._suggestion_key = made
    return self._suggestion

  def alignment(self, physics):
    """Alignment scores of every candidate connector pair in the current state."""
    pos, rot = self._furniture.part_poses(physics)
    return alignment.align_pairs(*self._table.world_frames(pos, rot), self._table)

  def try_connect(self, physics):
    """Connects the best attachable pair, if any; returns whether it did."""
    scores = self.alignment(physics)
    ok = scores.attachable(self._thresholds) & planner.open_pairs(self._table, self._state)
    if not ok.any():
      return False
    candidates = np.flatnonzero(ok)
    pair = candidates[np.argmin(scores.distance[candidates])]
    self._join(physics, pair, scores.twist[pair])
    return True

  def connect_in_place(self, physics, pair):
    """Connects connector pair `pair` whose parts already sit in their mating pose."""
    physics.forward()   # part poses are read from xpos/xmat, stale after an initializer
    self._join(physics, int(pair), self.alignment(physics).twist[pair])

  def _join(self, physics, pair, twist):
    table = self._table
    con_a, con_b = table.pair_a[pair], table.pair_b[pair]
    part_a, part_b = int(table.part[con_a]), int(table.part[con_b])
    pos, rot = (np.array(x) for x in self._furniture.part_poses(physics))
    cpos, crot = table.world_frames(pos, rot)
    group_a, group_b = self._state.group_members(part_a), self._state.group_members(part_b)
    # Aligned means R_b = R_a Rz(twist); the smaller group is moved to make it exact.
    if len(group_b) <= len(group_a):
      moving, moving_con, fixed_con = group_b, con_b, con_a
      target_rot = crot[con_a] @ geometry.rot_z(twist)
    else:
      moving, moving_con, fixed_con = group_a, con_a, con_b
      target_rot = crot[con_b] @ geometry.rot_z(-twist)
    delta = target_rot @ crot[moving_con].T
    for k in moving:
      rot[k] = delta @ rot[k]
      pos[k] = cpos[fixed_con] + delta @ (pos[k] - cpos[moving_con])
      part = self._furniture.parts[k]
      part.set_pose(physics, position=pos[k], quaternion=geometry.mat_to_quat(rot[k]))
      part.set_velocity(physics, velocity=np.zeros(3), angular_velocity=np.zeros(3))
    physics.forward()
    self._welds.activate(physics, part_a, part_b, pos[part_a], rot[part_a], pos[part_b], rot[part_b])
    self._state.connect(part_a, part_b, con_a, con_b)
    self._collisions.assign(physics, self._state.group_labels())
    self._robot.on_parts_moved(physics, moving)
