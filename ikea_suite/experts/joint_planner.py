"""Collision-free joint-space paths for one arm and the part it holds, planned with OMPL.

The scripted carry servos the tool in task space along an arc round the base and judges
the arm only at the goal; near the edge of the reach the differential IK drives a
joint into its limit, or the forearm onto the assembly, and the carry stalls. Here the
arm's joints are searched instead: IK solutions of the goal pose from several seeds are
the goals, a bidirectional RRT (OMPL's RRTConnect) joins them to the present joints, and
a state is valid when it lies within the joint ranges the IK keeps and MuJoCo's own
collision check, in a scratch copy of the state, finds the arm's links and the held part
(moved rigidly with the hand) clear of everything else: the assembly, the other parts,
the floor. The path is then followed through the same task-space actions a learner
sends, to the forward-kinematics tool poses of its waypoints (arm_motion.Unwinder).

OMPL is an optional dependency (the `planning` extra): without it `AVAILABLE` is False,
`plan_to_pose` returns None and the experts recover from a stalled carry as they did
before it existed. Planning is deterministic: OMPL's seed is set before each plan, and
the search stops after a fixed number of validity checks rather than after a time.
"""

import dataclasses

import mujoco
import numpy as np

from ikea_suite import errors
from ikea_suite import geometry

try:
  from ompl import base as _ob
  from ompl import geometric as _og
  from ompl import util as _ou
except ImportError:   # the `planning` extra is not installed
  _ob = _og = _ou = None
else:
  _ou.setLogLevel(_ou.LOG_NONE)   # reseeding per plan (see plan_to_pose) logs an error

AVAILABLE = _ob is not None

# Joint-space distance (rad, largest joint) between the checked states of a motion.
CHECK_STEP = 0.04
# Penetration (m) a contact may have and still count as clear: resting contacts read a
# fraction of a millimetre.
TOLERANCE = 0.002


class ArmScene:
  """Which joint configurations of one arm are valid, for a planner.

  A configuration is valid within the ranges the IK keeps the arm's joints in and when
  MuJoCo's collision check, with the arm at it, the other joints and every other body
  where they are now and the held part (if any) carried rigidly with the hand, finds no
  contact deeper than `tolerance` between the robot or the held part and anything else
  (the hand's own grip on the held part excepted). A contact already present at the
  start (a forearm resting on a shelf, the part on its mate) may stay, no deeper than it
  was, so the path can lead out of it.

  Args:
    robot: the environment's Manipulator.
    physics: the environment's physics (read once; never changed).
    arm: the arm's index.
    held_body: MuJoCo body id of the held part (any body of it), or None.
    tolerance: metres of penetration a contact may have and count as clear.
  """

  def __init__(self, robot, physics, arm, held_body=None, tolerance=TOLERANCE):
    model = physics.model
    self._model = model.ptr
    self._data = mujoco.MjData(self._model)
    self._data.qpos[:] = physics.data.qpos
    self._robot, self.arm, self._tolerance = robot, arm, tolerance
    self.q0 = robot.arm_qpos(physics)   # the IK joint vector now, every arm
    ik = robot.ik
    self._qpos = np.asarray(physics.bind(ik.joints).qposadr)   # IK order -> scene qpos
    self.index = ik.qpos_index[robot.ik_joint_indices(arm)]   # this arm's joints in q
    low, high = (b[self.index] for b in ik.limits)
    here = self.q0[self.index]
    # A joint pinned at its limit may read a hair beyond it: the range takes it in.
    self.low = np.minimum(np.where(np.isfinite(low), low, here - np.pi), here)
    self.high = np.maximum(np.where(np.isfinite(high), high, here + np.pi), here)
    self._site = int(physics.bind(robot.arms[arm].gripper.tcp_site).element_id)
    robot_geoms = np.asarray(physics.bind(robot.mjcf_model.find_all("geom")).element_id)
    in_hand = _bodies_below(model, model.body_weldid[model.site_bodyid[self._site]])
    self._robot_geoms = set(robot_geoms.tolist())
    self._hand_geoms = set(g for g in robot_geoms.tolist() if in_hand[model.geom_bodyid[g]])
    self._held_geoms, self._free_qpos, self._grip = set(), None, None
    if held_body is not None:
      free = _free_body(model, held_body)
      in_part = _bodies_below(model, free)
      self._held_geoms = set(np.flatnonzero(in_part[model.geom_bodyid]).tolist())
      self._free_qpos = int(model.jnt_qposadr[model.body_jntadr[free]])
      data = physics.data
      tcp_pos, tcp_rot = data.site_xpos[self._site], data.site_xmat[self._site].reshape(3, 3)
      part_rot = data.xmat[free].reshape(3, 3)
      self._grip = (tcp_rot.T @ (data.xpos[free] - tcp_pos), tcp_rot.T @ part_rot)
    self.checks = 0   # validity checks so far
    self._allowed = self.contacts(here)   # what touches at the start may stay, no deeper

  def full(self, arm_q):
    """The IK joint vector with this arm's joints at `arm_q` and the rest as now."""
    q = self.q0.copy()
    q[self.index] = arm_q
    return q

  def contacts(self, arm_q):
    """{(robot or held geom, other geom): metres they overlap} with this arm at `arm_q`."""
    model, data = self._model, self._data
    data.qpos[self._qpos] = self.full(arm_q)
    mujoco.mj_kinematics(model, data)
    if self._free_qpos is not None:
      tcp_pos, tcp_rot = data.site_xpos[self._site], data.site_xmat[self._site].reshape(3, 3)
      grip_pos, grip_rot = self._grip
      quat = np.empty(4)
      mujoco.mju_mat2Quat(quat, (tcp_rot @ grip_rot).ravel())
      data.qpos[self._free_qpos:self._free_qpos + 3] = tcp_pos + tcp_rot @ grip_pos
      data.qpos[self._free_qpos + 3:self._free_qpos + 7] = quat
      mujoco.mj_kinematics(model, data)
    mujoco.mj_collision(model, data)
    mine, hand, held = self._robot_geoms, self._hand_geoms, self._held_geoms
    out = {}
    contacts = data.contact
    for a, b, dist in zip(contacts.geom1.tolist(), contacts.geom2.tolist(),
                          contacts.dist.tolist()):
      if dist >= 0.0:
        continue
      ours_a, ours_b = a in mine or a in held, b in mine or b in held
      if ours_a and ours_b:
        # Only a link behind the hand against the held part: the grip is the hand's own.
        if not ((a in held and b in mine and b not in hand)
                or (b in held and a in mine and a not in hand)):
          continue
      elif not (ours_a or ours_b):
        continue
      pair = (a, b) if a < b else (b, a)
      out[pair] = max(out.get(pair, 0.0), -dist)
    return out

  def valid(self, arm_q):
    """True when `arm_q` (this arm's joints) lies within its ranges and is clear."""
    self.checks += 1
    if np.any(arm_q < self.low) or np.any(arm_q > self.high):
      return False
    allowed, tolerance = self._allowed, self._tolerance
    return all(depth <= allowed.get(pair, 0.0) + tolerance
               for pair, depth in self.contacts(arm_q).items())

  def motion_valid(self, a, b, step=CHECK_STEP):
    """True when the straight joint-space motion from `a` to `b` is valid throughout."""
    count = max(1, int(np.ceil(np.abs(b - a).max() / step)))
    return all(self.valid(a + (b - a) * (k / count)) for k in range(1, count + 1))


@dataclasses.dataclass(frozen=True)
class JointPath:
  """A planned path: IK joint vectors (every arm) from the present joints to the goal.

  Attributes:
    q: (waypoints, IK joints) joint vectors, the first the present one, consecutive ones
      at most `step` rad apart in any of the arm's joints.
    goal_miss: metres from the goal pose of the last waypoint's tool, plus 0.2 m per rad.
    checks: validity checks the plan took.
  """
  q: np.ndarray
  goal_miss: float
  checks: int


def ik_goals(robot, scene, goal_pos, goal_rot, seeds=6, max_miss=0.005, rng=None):
  """Valid IK solutions (this arm's joints) that put the tool at the world pose
  (goal_pos, goal_rot), solved from the first `seeds` of: the present joints, the home
  posture, random joint vectors within the ranges; none twice.

  Args:
    robot: the Manipulator.
    scene: the ArmScene that judges them.
    goal_pos: world position of the tool-centre point.
    goal_rot: world rotation of the tool.
    seeds: IK starts tried.
    max_miss: metres (plus 0.2 m per rad) a solution may miss the pose by.
    rng: numpy Generator for the random starts (default: seeded 0).

  Returns:
    [(arm joints, miss)], best first.
  """
  rng = np.random.default_rng(0) if rng is None else rng
  base_pos, base_rot = robot.base_pose
  target = (base_rot.T @ (goal_pos - base_pos), base_rot.T @ goal_rot)
  starts = [scene.q0, robot.ik.posture_near(scene.q0)]
  for _ in range(seeds - 2):
    q = scene.q0.copy()
    q[scene.index] = rng.uniform(scene.low, scene.high)
    starts.append(q)
  found = []
  for start in starts[:seeds]:
    targets = list(robot.ik.tcp_poses(start))
    targets[scene.arm] = target
    solution = robot.ik.solve(start, targets, iterations=60)
    pos, rot = robot.ik.tcp_poses(solution)[scene.arm]
    miss = float(np.linalg.norm(pos - target[0]) + 0.2 * np.linalg.norm(
        geometry.mat_to_axis_angle(rot @ target[1].T)))
    arm_q = solution[scene.index]
    if miss > max_miss or any(np.abs(arm_q - q).max() < 0.05 for q, _ in found):
      continue
    if scene.valid(arm_q):
      found.append((arm_q, miss))
  return sorted(found, key=lambda item: item[1])


def plan_to_pose(robot, physics, arm, goal_pos, goal_rot, held_body=None, max_checks=6000,
                 seed=0, step=0.05, ik_seeds=6):
  """A collision-free joint-space path for `arm` (and the part it holds) from its present
  joints to joints that put its tool at the world pose (goal_pos, goal_rot).

  OMPL's RRTConnect searches between the present joints and the IK goals (ik_goals) in
  the arm's joint space, each motion checked every CHECK_STEP rad (ArmScene); the path
  is then shortened by joining each waypoint to the farthest later one it sees, and
  divided into steps of at most `step` rad.

  Args:
    robot: the environment's Manipulator.
    physics: the environment's physics (not changed).
    arm: the arm's index.
    goal_pos: world position of the tool-centre point at the goal.
    goal_rot: world rotation of the tool at the goal.
    held_body: MuJoCo body id of the part the hand holds (it moves with the hand), or None.
    max_checks: validity checks the search may take (deterministic, unlike a time limit).
    seed: seed of OMPL's sampler and of the random IK starts.
    step: largest joint move (rad) between the returned waypoints.
    ik_seeds: IK starts for the goals (ik_goals).

  Returns:
    JointPath, or None: OMPL is absent, no IK goal is valid, the present joints are not
    (outside the ranges), or the search found no path within `max_checks`.
  """
  if not AVAILABLE:
    return None
  scene = ArmScene(robot, physics, arm, held_body)
  start = scene.q0[scene.index]
  if not scene.valid(start):
    return None
  goals = ik_goals(robot, scene, goal_pos, goal_rot, seeds=ik_seeds,
                   rng=np.random.default_rng(seed))
  if not goals:
    return None
  for goal, _ in goals:   # a straight joint move may do
    if scene.motion_valid(start, goal):
      return _finish(robot, scene, goal_pos, goal_rot, [start, goal], step)
  path = _search(scene, start, [g for g, _ in goals], max_checks, seed)
  if path is None:
    return None
  return _finish(robot, scene, goal_pos, goal_rot, _shortcut(scene, path), step)


def _search(scene, start, goals, max_checks, seed):
  """RRTConnect from `start` to any of `goals` (arm joint vectors); the waypoints, or None."""
  _ou.RNG.setSeed(seed + 1)   # every sampler made from here on starts from this seed
  dof = len(start)
  space = _ob.RealVectorStateSpace(dof)
  bounds = _ob.RealVectorBounds(dof)
  for i in range(dof):
    bounds.setLow(i, float(scene.low[i]))
    bounds.setHigh(i, float(scene.high[i]))
  space.setBounds(bounds)
  setup = _og.SimpleSetup(space)
  setup.setStateValidityChecker(lambda s: scene.valid(np.array([s[i] for i in range(dof)])))
  info = setup.getSpaceInformation()
  info.setStateValidityCheckingResolution(CHECK_STEP / space.getMaximumExtent())
  state = space.allocState()
  for i in range(dof):
    state[i] = float(start[i])
  setup.setStartState(state)
  goal_states = _ob.GoalStates(info)
  for goal in goals:
    g = space.allocState()
    for i in range(dof):
      g[i] = float(goal[i])
    goal_states.addState(g)
  setup.setGoal(goal_states)
  setup.setPlanner(_og.RRTConnect(info))
  budget = scene.checks + max_checks
  solved = setup.solve(_ob.PlannerTerminationCondition(lambda: scene.checks > budget))
  if not (solved and setup.haveExactSolutionPath()):
    return None
  states = setup.getSolutionPath().getStates()
  return [np.array([s[i] for i in range(dof)]) for s in states]


def _shortcut(scene, path):
  """The path with each waypoint joined to the farthest later one it reaches straight."""
  out, i = [path[0]], 0
  while i < len(path) - 1:
    j = len(path) - 1
    while j > i + 1 and not scene.motion_valid(path[i], path[j]):
      j -= 1
    out.append(path[j])
    i = j
  return out


def _finish(robot, scene, goal_pos, goal_rot, path, step):
  """JointPath of `path` (arm joint vectors) divided into moves of at most `step` rad."""
  dense = [path[0]]
  for a, b in zip(path[:-1], path[1:]):
    count = max(1, int(np.ceil(np.abs(b - a).max() / step)))
    dense.extend(a + (b - a) * (k / count) for k in range(1, count + 1))
  q = np.array([scene.full(arm_q) for arm_q in dense])
  base_pos, base_rot = robot.base_pose
  pos, rot = robot.ik.tcp_poses(q[-1])[scene.arm]
  miss = float(np.linalg.norm(base_rot @ pos + base_pos - goal_pos) + 0.2 * np.linalg.norm(
      geometry.mat_to_axis_angle(base_rot @ rot @ goal_rot.T)))
  return JointPath(q=q, goal_miss=miss, checks=scene.checks)


def _bodies_below(model, root):
  """(nbody,) bool: `root` and the bodies below it in the tree."""
  below = np.zeros(model.nbody, dtype=bool)
  below[root] = True
  for body in range(root + 1, model.nbody):   # parents come before their children
    below[body] = below[model.body_parentid[body]]
  return below


def _free_body(model, body):
  """The body with the free joint that `body` moves with (itself or an ancestor)."""
  given = body
  while body > 0:
    if model.body_jntnum[body] and model.jnt_type[model.body_jntadr[body]] == int(
        mujoco.mjtJoint.mjJNT_FREE):
      return body
    body = int(model.body_parentid[body])
  raise errors.IkeaSuiteError(f"body {given} moves with no free joint: it is not a loose part")
