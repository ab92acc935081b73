"""The assembly task: connect every part of a furniture into one rigid assembly."""


import collections

import numpy as np
from dm_control import composer
from dm_control.composer.observation import observable as observable_lib
from dm_control.composer.variation import distributions
from dm_env import specs

from ikea_suite import config as config_lib
from ikea_suite import errors
from ikea_suite import geometry
from ikea_suite import mujoco_arrays
from ikea_suite import observations
from ikea_suite import physics_settings
from ikea_suite.assembly import sequence
from ikea_suite.tasks import alignment
from ikea_suite.tasks import arm_placement
from ikea_suite.tasks import assembly_state
from ikea_suite.tasks import collision_groups
from ikea_suite.tasks import framing
from ikea_suite.tasks import placement
from ikea_suite.tasks import planner
from ikea_suite.tasks import rewards
from ikea_suite.tasks import welds

CONNECT_ACTION = "connect"
# How deep (m) a connection may push the moving group into the floor or into a
# part of another group. Deeper and the connection is refused: snapping moves a
# part by up to the distance threshold about a connector, which at the far end
# of a 2 m panel can be decimetres, and MuJoCo would then fling it out.
SNAP_PENETRATION_TOL = 0.005


class Assembly(composer.Task):
  """Long-horizon furniture assembly (Lee et al. 2019) as a composer task.

  The action is the robot's actions followed by `connect`. When `connect` is
  on (> 0) the task checks every free mating connector pair between different
  assembled groups; the best-aligned attachable pair is snapped together
  (the smaller group moves), welded, and its groups stop colliding.

  A connection is refused (and reported in `blocked_connections`) when the
  snap would push the moving group more than `SNAP_PENETRATION_TOL` into the
  floor or another group. After a connection every other free mating pair
  inside the new group whose frames coincide within the thresholds is welded
  too, so loops close and the assembly is rigid (`loop_closures`).

  Reward: `connection_reward` for each new connection plus `completion_bonus`
  when the last part joins, which also ends the episode (discount 0).
  With `reward="dense"`, staged shaping instead (tasks/rewards.py).

  Args:
    arena, furniture, robot: the entities.
    config: the task's options (config.TaskConfig; None: the defaults), resolved here for
      this furniture and robot and kept as `config`.
    initializer: a placement.PartInitializer; None: `part_layout`'s for the robot.
  """

  def __init__(self, arena, furniture, robot, config=None, initializer=None):
    self._arena, self._furniture, self._robot = arena, furniture, robot
    config = (config_lib.TaskConfig() if config is None else config).resolved(
        len(furniture.parts), scattered=robot.reach_zone is None, scale=furniture.scale)
    self._config = config
    physics_settings.configure_arena(arena.mjcf_model)
    self._thresholds = alignment.Thresholds.of(config)
    connection_reward, completion_bonus = config.connection_reward, config.completion_bonus
    self._connection_reward, self._completion_bonus = connection_reward, completion_bonus
    furniture.attach_to(arena)
    robot.mount(arena)
    framing.frame_front_camera(arena, furniture, robot, config.spread)
    self._table = furniture.connectors
    self._state = assembly_state.AssemblyState(len(furniture.parts), len(self._table))
    self._welds = welds.PartWelds(arena, furniture)
    self._collisions = collision_groups.CollisionGroups(len(furniture.parts))
    self._root = planner.root_part(furniture.spec)
    self._order = sequence.assembly_order(furniture.spec, self._root)
    self._design_pairs = placement.design_pairs(furniture.spec, self._table)
    self.set_timesteps(control_timestep=config.control_timestep,
                       physics_timestep=config.physics_timestep)
    robot.bind_scene(arena, furniture, self._state, self.control_timestep)
    if initializer is None:
      initializer = part_layout(furniture, robot, arena.support, config)
    if not isinstance(initializer, placement.PartInitializer):
      raise errors.IkeaSuiteError(
          f"initializer must be a placement.PartInitializer (it names the pairs it placed "
          f"mated), got {type(initializer).__name__}")
    self._initializer = initializer
    # Static props the placement needs (the panel rack), fixed to the arena.
    self._fixtures = list(initializer.fixtures)
    for fixture in self._fixtures:
      arena.attach(fixture)
    self._step_reward = 0.0
    self._blocked = ()
    self._suggestion_key = None
    self._dense = rewards.make(config.reward, self, connection_reward,
                               completion_bonus)  # None: sparse
    self._task_observables = {
        "connections": mujoco_arrays.FreshGeneric(lambda physics: self._state.adjacency.copy()),
        "connectors_used": mujoco_arrays.FreshGeneric(
            lambda physics: self._state.connector_used.astype(np.float64)),
        "next_pair": mujoco_arrays.FreshGeneric(lambda physics: self.suggested_parts().astype(np.float64)),
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
  def observables(self):
    """Every observable under its vocabulary key (observations.py), never the furniture's or
    the robot's model name: `furniture/`, `task/`, `robot/`, `cameras/` (any image)."""
    robot_entities = set(map(id, self._robot.iter_entities()))
    named = collections.OrderedDict(
        (observations.key("task", name), obs) for name, obs in self._task_observables.items())
    for entity in self.root_entity.iter_entities():
      if entity is self._furniture:
        prefix = "furniture/"
      elif entity is self._robot:
        prefix = "robot/"
      elif id(entity) in robot_entities:   # a robot's own parts (dm_control's Jaco hand)
        prefix = f"robot/{entity.mjcf_model.model}/"
      elif entity.mjcf_model.model == "cameras":
        prefix = "cameras/"
      else:   # composer's naming for entities that give none by default (arena, props)
        identifier = entity.mjcf_model.full_identifier
        prefix = f"{identifier}/" if identifier else ""
      for name, obs in entity.observables.as_dict(fully_qualified=False).items():
        if isinstance(obs, observable_lib.MJCFCamera):
          full = observations.key("cameras", name)
        else:
          full = prefix + name
        if full in named:
          raise errors.IkeaSuiteError(
              f"two observations are named {full!r}: choose the camera once (cameras= or "
              f"wrist_camera=)")
        named[full] = obs
    return named

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
    physics_settings.configure_contacts(physics.model)
    fixture_geoms = [g for fixture in self._fixtures for g in fixture.geoms]
    physics_settings.configure_supports(
        physics.model, physics.bind(list(self._arena.support_geoms) + fixture_geoms).element_id)
    self._welds.after_compile(physics)
    self._collisions.after_compile(self._furniture)
    model = physics.model
    part_of_body = np.full(model.nbody, -1)
    part_of_body[self._furniture.body_ids] = np.arange(len(self._furniture.parts))
    # Per geom: its part index, -1 for robot geoms, -2 for static world geoms (floor, walls).
    self._geom_part = part_of_body[model.geom_bodyid]
    self._geom_part[model.geom_bodyid == 0] = -2
    if fixture_geoms:   # the rack is static too
      self._geom_part[physics.bind(fixture_geoms).element_id] = -2

  def initialize_episode(self, physics, random_state):
    self._state.reset()
    self._blocked = ()
    self._suggestion_key = None
    self._welds.reset(physics)
    self._collisions.reset(physics)
    self._initializer(physics, random_state)
    # Curriculum initializers leave connector pairs they placed assembled.
    for pair in self._initializer.preassembled_pairs:
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
  def config(self):
    """The task's options, resolved for this furniture and robot (config.TaskConfig)."""
    return self._config

  @property
  def connection_reward(self):
    """Sparse reward paid for each new connection."""
    return self._connection_reward

  @property
  def completion_bonus(self):
    """Sparse reward paid once when the furniture is complete."""
    return self._completion_bonus

  def welded_part_pairs(self, physics):
    """Sorted (i, j) part pairs whose weld is on."""
    return self._welds.active_pairs(physics)

  def weld_relative_poses(self, physics):
    """{(i, j): (7,) pose of part j in part i's frame (m; quaternion w x y z)} for each weld on."""
    return self._welds.relative_poses(physics)

  @property
  def loop_closures(self):
    """Connector pairs welded because they came to coincide, not by a connect action."""
    return tuple(self._state.closures)

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

  @property
  def initializer(self):
    """The placement.PartInitializer that lays the parts out each episode."""
    return self._initializer

  @property
  def design_pairs(self):
    """Indices of the candidate connector pairs that coincide in the assembled design."""
    return self._design_pairs

  @property
  def assembly_order(self):
    """Part indices in the buildable order the planner suggests, root first."""
    return self._order

  def suggested_parts(self):
    """[moving part, target part] of the planner's next connection, or [-1, -1]."""
    made = len(self._state.connections)
    if self._suggestion_key != made:  # the plan changes only when a connection is made
      suggestion = planner.next_pair(self._table, self._state, self._order, self._design_pairs)
      self._suggestion = np.array([-1, -1]) if suggestion is None else np.array(suggestion[1:])
      self._suggestion_key = made
    return self._suggestion

  def alignment(self, physics):
    """Alignment scores of every candidate connector pair in the current state."""
    pos, rot = self._furniture.part_poses(physics)
    return alignment.align_pairs(*self._table.world_frames(pos, rot), self._table)

  def try_connect(self, physics):
    """Connects the nearest attachable pair that can snap without collision; returns
    whether it connected. Refused pairs are explained in `blocked_connections`."""
    scores = self.alignment(physics)
    ok = scores.attachable(self._thresholds) & planner.open_pairs(self._table, self._state)
    for pair in sorted(np.flatnonzero(ok), key=lambda k: scores.distance[k]):
      if self._join(physics, int(pair), scores.twist[pair]):
        return True
    return False

  def connect_in_place(self, physics, pair):
    """Connects connector pair `pair` whose parts already sit in their mating pose."""
    physics.forward()   # part poses are read from xpos/xmat, stale after an initializer
    if not self._join(physics, int(pair), self.alignment(physics).twist[pair]):
      raise composer.EpisodeInitializationError(
          f"could not join preassembled pair {pair}: {self._blocked[-1]}")

  def _join(self, physics, pair, twist):
    table = self._table
    con_a, con_b = table.pair_a[pair], table.pair_b[pair]
    part_a, part_b = int(table.part[con_a]), int(table.part[con_b])
    pos, rot = (np.array(x) for x in self._furniture.part_poses(physics))
    cpos, crot = table.world_frames(pos, rot)
    group_a, group_b = self._state.group_members(part_a), self._state.group_members(part_b)
    # The smaller group is moved to make the connector frames coincide exactly.
    if len(group_b) <= len(group_a):
      moving, fixed, moving_con = group_b, group_a, con_b
    else:
      moving, fixed, moving_con = group_a, group_b, con_a
    target_pos, target_rot = table.mated_frame(pair, moving_con, cpos, crot, twist)
    saved_qpos, saved_qvel = physics.data.qpos.copy(), physics.data.qvel.copy()
    delta = target_rot @ crot[moving_con].T
    for k in moving:
      rot[k] = delta @ rot[k]
      pos[k] = target_pos + delta @ (pos[k] - cpos[moving_con])
      self._furniture.set_part_pose(physics, k, pos[k], geometry.mat_to_quat(rot[k]))
    physics.forward()
    collision = self._snap_collision(physics, moving, fixed)
    if collision:
      physics.data.qpos[:], physics.data.qvel[:] = saved_qpos, saved_qvel
      physics.forward()
      names = self._table.names
      self._blocked += (f"{names[con_a]} + {names[con_b]}: {collision}",)
      return False
    self._welds.activate(physics, part_a, part_b, pos[part_a], rot[part_a], pos[part_b], rot[part_b])
    self._state.connect(part_a, part_b, con_a, con_b)
    self._close_loops(physics)
    self._collisions.assign(physics, self._state.group_labels())
    self._robot.on_parts_moved(physics, moving)
    return True

  def _snap_collision(self, physics, moving, fixed):
    """Why the snapped `moving` group may not stay (too deep in the floor or in a part of a
    third group), or "" when it may."""
    data = physics.data
    if not data.ncon:
      return ""
    contacts = data.contact
    deep = contacts.dist < -SNAP_PENETRATION_TOL
    if not deep.any():
      return ""
    owner = np.stack([self._geom_part[contacts.geom1[deep]], self._geom_part[contacts.geom2[deep]]])
    moving_set = np.isin(owner, moving)
    obstacle = (owner == -2) | ((owner >= 0) & ~np.isin(owner, moving) & ~np.isin(owner, fixed))
    hits = (moving_set[0] & obstacle[1]) | (moving_set[1] & obstacle[0])
    if not hits.any():
      return ""
    k = int(np.argmax(np.where(hits, -contacts.dist[deep], -np.inf)))
    other = owner[1, k] if moving_set[0, k] else owner[0, k]
    if other == -2:   # a static geom: the floor, or the work table's top, legs or pedestal
      static = contacts.geom2[deep][k] if moving_set[0, k] else contacts.geom1[deep][k]
      what = "the " + (physics.model.geom(static).name.split("/")[-1].replace("_", " ") or "floor")
    else:
      what = f"part {self._furniture.spec.parts[other].name!r}"
    return (f"snapping would push it {-contacts.dist[deep][k] * 1000:.0f} mm into {what} "
            f"(limit {SNAP_PENETRATION_TOL * 1000:.0f} mm)")

  def _close_loops(self, physics):
    """Welds every free mating pair inside one group whose frames now coincide."""
    pos, rot = self._furniture.part_poses(physics)
    scores = alignment.align_pairs(*self._table.world_frames(pos, rot), self._table)
    table, state = self._table, self._state
    groups = state.group_labels()
    inside = ((groups[table.part[table.pair_a]] == groups[table.part[table.pair_b]])
              & ~state.connector_used[table.pair_a] & ~state.connector_used[table.pair_b])
    candidates = np.flatnonzero(inside & scores.attachable(self._thresholds))
    for pair in sorted(candidates, key=lambda k: scores.distance[k]):
      con_a, con_b = table.pair_a[pair], table.pair_b[pair]
      if state.connector_used[con_a] or state.connector_used[con_b]:
        continue
      part_a, part_b = int(table.part[con_a]), int(table.part[con_b])
      if not self._welds.is_active(physics, part_a, part_b):
        self._welds.activate(physics, part_a, part_b, pos[part_a], rot[part_a], pos[part_b],
                             rot[part_b])
      state.close_loop(part_a, part_b, con_a, con_b)


def part_layout(furniture, robot, support, config):
  """How the parts lie at the start of an episode, the one place it is chosen: scattered
  in a ring around the furniture for a robot that reaches everywhere (the Cursor), within
  its reach for a fixed-base arm (its `reach_zone`).

  Args:
    furniture: the Furniture prop.
    robot: the robot entity.
    support: the arenas.support.Support the parts lie on.
    config: the resolved config.TaskConfig (spread, yaw_range, preassembled).
  Returns:
    A placement.PartInitializer.
  """
  if robot.reach_zone is None:
    return placement.ScatteredParts(
        furniture, spread=config.spread, preassembled=config.preassembled,
        yaw=distributions.Uniform(-config.yaw_range, config.yaw_range))
  return arm_placement.for_reach_zone(furniture, robot.reach_zone, support, config.spread,
                                      config.yaw_range, config.preassembled)
