"""A scripted Cursor policy that assembles any furniture from privileged state.

Cursor 0 lifts the root part to its assembled pose (raised by `lift`) and
holds it there. Cursor 1 fetches the planner's next part: grab, raise, fly
to a staging point outside the assembly, approach along the connector's
side, align, and issue connect. It emits the same 15-number action a learning
agent does; nothing is moved by hand.
"""

import enum

import numpy as np

from ikea_suite import geometry
from ikea_suite.oracle import targets
from ikea_suite.tasks import planner

_PER_CURSOR = 7


class Phase(enum.Enum):
  REACH = "reach"       # fly the empty cursor to the part's grasp point
  RAISE = "raise"       # hold the part and lift it clear of the floor
  STAGE = "stage"       # carry it to a point outside the assembly, rotated to fit
  APPROACH = "approach" # move in to just short of the mating pose
  INSERT = "insert"     # close the last gap and connect


class CursorOracle:
  """Call with a TimeStep; returns an action for `env` (an ikea_suite cursor environment)."""

  def __init__(self, env, lift=0.15, approach=0.10, stage=0.30, gain=0.6, tolerance=0.5):
    self._env = env
    self._lift, self._approach, self._stage, self._gain = lift, approach, stage, gain
    self._tolerance = tolerance   # fraction of each threshold to reach before connecting
    self.reset()

  def reset(self):
    self._phase = Phase.REACH
    self._base_phase = Phase.REACH
    self._connections = 0

  # -- low-level drives --------------------------------------------------------

  def _cursor(self, i):
    return self._env.task.robot.cursor_pose(self._env.physics, i)

  def _move_to(self, action, i, target):
    robot = self._env.task.robot
    pos, _ = self._cursor(i)
    step = robot._move_speed * self._env.control_timestep()
    action[i * _PER_CURSOR:i * _PER_CURSOR + 3] = np.clip(self._gain * (target - pos) / step, -1, 1)

  def _drive_part(self, action, i, part, target_pos, target_rot):
    """Cursor i moves and turns so that the part it holds reaches the target pose."""
    physics, task = self._env.physics, self._env.task
    robot, dt = task.robot, self._env.control_timestep()
    part_pos, part_rot = targets.part_pose(physics, task.furniture, part)
    rot_error = geometry.mat_to_axis_angle(target_rot @ part_rot.T)
    rot_cmd = np.clip(self._gain * rot_error / (robot._rotate_speed * dt), -1, 1)
    turn = geometry.axis_angle_to_mat(rot_cmd * robot._rotate_speed * dt)
    cursor_pos, _ = self._cursor(i)
    # Turning about the cursor also swings the part; move the cursor to cancel that.
    swing = (turn - np.eye(3)) @ (part_pos - cursor_pos)
    move = self._gain * (target_pos - part_pos) - swing
    base = i * _PER_CURSOR
    action[base:base + 3] = np.clip(move / (robot._move_speed * dt), -1, 1)
    action[base + 3:base + 6] = rot_cmd
    return np.linalg.norm(target_pos - part_pos), np.linalg.norm(rot_error)

  def _holds(self, i, part):
    held = self._env.task.robot.held_parts[i]
    return held >= 0 and self._env.task.state.same_group(held, part)

  # -- the two cursors' jobs ---------------------------------------------------

  def _base_target(self):
    spec = self._env.task.furniture.spec.parts[self._env.task.root_part]
    return spec.pos + np.array([0.0, 0.0, self._lift]), spec.rot

  def _fetch(self, action, i, part, raise_height=None):
    """REACH then grab; returns True once cursor i holds `part`."""
    physics, furniture = self._env.physics, self._env.task.furniture
    if self._holds(i, part):
      action[i * _PER_CURSOR + 6] = 1.0
      return True
    point = targets.grasp_point(physics, furniture, part)
    self._move_to(action, i, point)
    pos, _ = self._cursor(i)
    if np.linalg.norm(point - pos) < 0.01:
      action[i * _PER_CURSOR + 6] = 1.0
    return False

  def _raise_height(self, part):
    bounds = self._env.task.furniture.spec.parts[part].bounds
    return 0.5 * np.linalg.norm(bounds[1] - bounds[0]) + 0.05

  def _hold_base(self, action):
    """Cursor 0: fetch the root part, raise it, bring it to the assembly pose; True when there."""
    root = self._env.task.root_part
    if not self._fetch(action, 0, root):
      self._base_phase = Phase.REACH
      return False
    action[6] = 1.0
    physics, furniture = self._env.physics, self._env.task.furniture
    pos, rot = targets.part_pose(physics, furniture, root)
    target_pos, target_rot = self._base_target()
    if self._base_phase == Phase.REACH:
      self._base_phase = Phase.RAISE
    if self._base_phase == Phase.RAISE:
      height = self._raise_height(root)
      self._drive_part(action, 0, root, np.array([pos[0], pos[1], max(height, pos[2])]), rot)
      if pos[2] > height - 0.02:
        self._base_phase = Phase.STAGE
      return False
    distance, angle = self._drive_part(action, 0, root, target_pos, target_rot)
    return distance < 0.02 and angle < 0.05

  def _bring_part(self, action, pair, moving, base_ready):
    """Cursor 1: carry `moving` to its mating pose; returns True when it should connect."""
    physics, task = self._env.physics, self._env.task
    if not self._fetch(action, 1, moving):
      self._phase = Phase.REACH
      return False
    action[13] = 1.0
    if self._phase == Phase.REACH:
      self._phase = Phase.RAISE
    pos, rot = targets.part_pose(physics, task.furniture, moving)
    if self._phase == Phase.RAISE:
      height = self._raise_height(moving)
      self._drive_part(action, 1, moving, np.array([pos[0], pos[1], max(height, pos[2])]), rot)
      if pos[2] > height - 0.02 and base_ready:
        self._phase = Phase.STAGE
      return False
    target_pos, target_rot, side = targets.mating_target(physics, task.furniture, pair, moving)
    pre = target_pos + self._approach * side
    outward = np.array([target_pos[0], target_pos[1], 0.0]) - np.append(self._base_target()[0][:2], 0)
    outward = outward / max(np.linalg.norm(outward), 1e-6)
    goals = {Phase.STAGE: (pre + self._stage * outward, 0.05, 0.2),
             Phase.APPROACH: (pre, 0.02, 0.05),
             Phase.INSERT: (target_pos, None, None)}
    goal, pos_tol, rot_tol = goals[self._phase]
    distance, angle = self._drive_part(action, 1, moving, goal, target_rot)
    if self._phase == Phase.STAGE and distance < pos_tol and angle < rot_tol:
      self._phase = Phase.APPROACH
    elif self._phase == Phase.APPROACH and distance < pos_tol and angle < rot_tol:
      self._phase = Phase.INSERT
    elif self._phase == Phase.INSERT:
      scores = task.alignment(physics)
      t = task.thresholds
      return bool(scores.distance[pair] < self._tolerance * t.distance
                  and scores.up_cos[pair] > 1 - self._tolerance * (1 - t.up_cos)
                  and scores.forward_cos[pair] > 1 - self._tolerance * (1 - t.forward_cos))
    return False

  def __call__(self, timestep=None):
    task = self._env.task
    action = np.zeros(self._env.action_spec().shape)
    if len(task.state.connections) != self._connections:
      self._connections = len(task.state.connections)
      self._phase = Phase.REACH
    suggestion = planner.next_pair(task.furniture.connectors, task.state, task.root_part)
    base_ready = self._hold_base(action)
    if suggestion is None:
      return action
    pair, moving, _ = suggestion
    if self._bring_part(action, pair, moving, base_ready):
      action[-1] = 1.0
    return action
