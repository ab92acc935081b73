"""A single arm's action in one world on the device: task-space targets, batched
differential IK, joint-position targets and the gripper command.

Task-space mode means what it means on the CPU (robots/control_modes.py,
TaskSpaceTargets): the tool target moves by `max_translation` m and turns by
`max_rotation` rad (world axes) per control step at an action of 1, is kept within
0.1 m of the measured tool and inside the arm's workspace box, and once per control
step an IK step from the measured joints gives the position actuators' targets.

The IK step solves the CPU's mink QP (robots/ik.py, ik_qp.py) itself: the tool's
FrameTask error, the log of its pose in the target's frame (cost 1 on the translation
part, 0.5 on the rotation part), a posture term towards home (cost 1e-2),
Levenberg-Marquardt damping 1e-3, and each joint's step kept within the velocity limit
(VELOCITY_LIMIT rad/s over the control step) and within 0.95 of its distance to the
ranges the CPU IK keeps in (mink's ConfigurationLimit; physical limits with the robot's
IK_WORKING_RANGES). Where the CPU solves that box-constrained QP with DAQP, `box_qp`
solves it by projected Newton iterations; tests/test_batch_arm.py finds the two paths'
tools within rounding of each other over a sequence of moves and turns, for every arm.

The error's Jacobian comes from forward kinematics of the arm's kinematic chain written
in jax (`Chain`), taken from the compiled model's body, joint and site frames and
differentiated with jax.jacfwd: it needs nothing from MJX, so it runs the same on
MJX's Warp and JAX implementations.
"""

import typing

import jax
import jax.numpy as jnp
import mujoco
import numpy as np

from ikea_suite import errors
from ikea_suite.batch import rigid

POSITION_COST, ORIENTATION_COST = 1.0, 0.5    # mink FrameTask costs (robots/ik.py)
POSTURE_COST = 1e-2                           # robots/ik.py _POSTURE_COST
DAMPING = 1e-3                                # robots/ik.py _DAMPING
MAX_LAG = 0.1                                 # TaskSpaceTargets' default max_lag, m
CONFIGURATION_GAIN = 0.95                     # mink ConfigurationLimit's default gain


class Chain(typing.NamedTuple):
  """The fixed frames of the kinematic chain from the world to the tool site.

  Per link on the path (world's child first): its body offset in the parent
  (pos (l, 3), rot (l, 3, 3)), whether it carries the hinge of arm joint `joint[l]`
  (-1: rigid), the hinge axis and anchor in the body frame; then the tool site's
  offset in the last body.
  """
  pos: jnp.ndarray
  rot: jnp.ndarray
  joint: tuple        # Python ints: the chain's structure is fixed when tracing
  axis: jnp.ndarray
  anchor: jnp.ndarray
  site_pos: jnp.ndarray
  site_rot: jnp.ndarray


def _quat_mat(quat):
  out = np.empty(9)
  mujoco.mju_quat2Mat(out, np.asarray(quat, dtype=float))
  return out.reshape(3, 3)


def chain(model, site, arm_qpos):
  """The Chain of `site` in the compiled MjModel `model`; `arm_qpos` (joints,) the qpos
  address of each arm joint (their order is the order of the chain's joint indices).

  Raises:
    IkeaSuiteError: a joint on the path that is not an arm hinge.
  """
  bodies = []
  body = int(model.site_bodyid[site])
  while body != 0:
    bodies.append(body)
    body = int(model.body_parentid[body])
  bodies.reverse()
  index = {int(a): i for i, a in enumerate(arm_qpos)}
  joint, axis, anchor = [], [], []
  for b in bodies:
    count = int(model.body_jntnum[b])
    if count > 1:
      raise errors.IkeaSuiteError(f"body {b} of the arm chain has {count} joints")
    if count == 0:
      joint.append(-1), axis.append(np.zeros(3)), anchor.append(np.zeros(3))
      continue
    j = int(model.body_jntadr[b])
    adr = int(model.jnt_qposadr[j])
    if model.jnt_type[j] != mujoco.mjtJoint.mjJNT_HINGE or adr not in index:
      raise errors.IkeaSuiteError(f"joint {model.joint(j).name!r} on the arm chain is not an "
                                  f"arm hinge")
    joint.append(index[adr]), axis.append(model.jnt_axis[j]), anchor.append(model.jnt_pos[j])
  f = lambda x: rigid.real(np.asarray(x))
  return Chain(pos=f(model.body_pos[bodies]), rot=f([_quat_mat(model.body_quat[b]) for b in bodies]),
               joint=tuple(joint), axis=f(axis), anchor=f(anchor),
               site_pos=f(model.site_pos[site]), site_rot=f(_quat_mat(model.site_quat[site])))


def _axis_rot(axis, angle):
  """Rotation (3, 3) by `angle` about unit `axis` (Rodrigues)."""
  x, y, z = axis
  k = jnp.array([[0.0, -z, y], [z, 0.0, -x], [-y, x, 0.0]])
  return jnp.eye(3) + jnp.sin(angle) * k + (1 - jnp.cos(angle)) * (k @ k)


def body_poses(chain_, q):
  """World positions (l, 3) and rotations (l, 3, 3) of the chain's bodies (world's child
  first) at arm joints q (joints,), as MuJoCo's forward kinematics places them."""
  pos, rot = jnp.zeros(3, dtype=q.dtype), jnp.eye(3, dtype=q.dtype)
  out_pos, out_rot = [], []
  for i in range(chain_.pos.shape[0]):
    pos = pos + rot @ chain_.pos[i]
    rot = rot @ chain_.rot[i]
    j = chain_.joint[i]
    if j >= 0:
      turn = _axis_rot(chain_.axis[i], q[j])
      anchor = pos + rot @ chain_.anchor[i]
      rot = rot @ turn
      pos = anchor - rot @ chain_.anchor[i]
    out_pos.append(pos)
    out_rot.append(rot)
  return jnp.stack(out_pos), jnp.stack(out_rot)


def tool_pose(chain_, q):
  """World position (3,) and rotation (3, 3) of the tool site at arm joints q (joints,),
  as MuJoCo's forward kinematics places it."""
  pos, rot = body_poses(chain_, q)
  return pos[-1] + rot[-1] @ chain_.site_pos, rot[-1] @ chain_.site_rot


def rotation_vector(rot):
  """Axis times angle (3,) of a rotation matrix (angle in [0, pi])."""
  q = rigid.mat_to_quat(rot)
  norm = jnp.linalg.norm(q[1:])
  angle = 2.0 * jnp.arctan2(norm, q[0])
  return q[1:] * jnp.where(norm > 1e-12, angle / jnp.maximum(norm, 1e-12), 2.0)


def se3_log(pos, rot):
  """The tangent vector [v, omega] (6,) of the rigid transform (pos (3,), rot (3, 3)), as
  mink's SE3.log gives it: omega the rotation vector, v = V(omega)^-1 pos. Smooth at the
  identity (small-angle series), so that jax differentiates it there."""
  quat = rigid.mat_to_quat(rot)                     # w >= 0: angle in [0, pi]
  w, xyz = quat[0], quat[1:]
  n2 = jnp.dot(xyz, xyz)
  small = n2 < 1e-8
  n = jnp.sqrt(jnp.where(small, 1.0, n2))
  # 2 atan2(n, w) / n, and its series in n where n is tiny (w is then close to 1).
  factor = jnp.where(small, 2.0 / w * (1.0 - n2 / (3.0 * w * w)), 2.0 * jnp.arctan2(n, w) / n)
  omega = xyz * factor
  t2 = jnp.dot(omega, omega)
  near = t2 < 1e-4
  half = 0.5 * jnp.sqrt(jnp.where(near, 1.0, t2))
  coeff = jnp.where(near, 1.0 / 12.0 + t2 / 720.0,
                    (1.0 - half * jnp.cos(half) / jnp.sin(half)) / jnp.where(near, 1.0, t2))
  cross = jnp.cross(omega, pos)
  v = pos - 0.5 * cross + coeff * jnp.cross(omega, cross)
  return jnp.concatenate([v, omega])


def frame_error(chain_, q, target_pos, target_rot):
  """mink's FrameTask error of the tool at joints q: the log of the tool's pose in the
  target's frame (6,), zero on target."""
  pos, rot = tool_pose(chain_, q)
  return se3_log(target_rot.T @ (pos - target_pos), target_rot.T @ rot)


def ik_step(chain_, q, target_pos, target_rot, home, low, high, max_step):
  """Arm joint targets after one differential IK step from q towards the target.

  Args:
    chain_: the arm's Chain.
    q: (joints,) measured joints.
    target_pos, target_rot: world tool target.
    home: (joints,) posture target.
    low, high: (joints,) ranges the IK keeps in.
    max_step: largest change (rad) of each joint in the step (velocity limit x control
      step).

  Returns:
    (joints,) joint targets.
  """
  q = jnp.clip(q, low, high)
  # A joint without range (the Jaco's 1, 4, 5 and 6) is pulled towards the home angle's
  # whole-turn equivalent nearest it, as DifferentialIK.posture_near does.
  endless = jnp.isinf(low) & jnp.isinf(high)
  home = jnp.where(endless, home + 2 * jnp.pi * jnp.round((q - home) / (2 * jnp.pi)), home)

  def error_and_value(x):   # the error, and again as jacfwd's aux: one kinematics pass
    error = frame_error(chain_, x, target_pos, target_rot)
    return error, error

  jac, error = jax.jacfwd(error_and_value, has_aux=True)(q)   # (6, n), (6,)
  weight = jnp.array([POSITION_COST] * 3 + [ORIENTATION_COST] * 3) ** 2
  n = q.shape[0]
  hessian = jac.T @ (weight[:, None] * jac) + (POSTURE_COST ** 2 + DAMPING) * jnp.eye(n)
  gradient = -jac.T @ (weight * error) + POSTURE_COST ** 2 * (home - q)
  lower = jnp.maximum(CONFIGURATION_GAIN * (low - q), -max_step)
  upper = jnp.minimum(CONFIGURATION_GAIN * (high - q), max_step)
  dq = box_qp(hessian, gradient, lower, upper)
  return jnp.clip(q + dq, low, high)


# Projected Newton iterations of box_qp, at most, and the step lengths its line search
# tries (1, 1/2, ... 1/2^(LINE_SEARCH_STEPS - 1)). On IK-shaped problems (tests/test_batch_arm.py)
# it meets the optimality conditions within 8 iterations.
BOX_QP_ITERATIONS = 30
LINE_SEARCH_STEPS = 24
_ARMIJO = 1e-4


def box_qp(hessian, gradient, lower, upper, iterations=BOX_QP_ITERATIONS):
  """Minimises f(x) = 0.5 x'Hx - g'x subject to lower <= x <= upper (H positive definite).

  Bertsekas' projected Newton method: the joints held at a bound the slope pushes
  against are kept there; the others take the Newton step of the problem reduced to
  them; the step is projected onto the box and shortened until it decreases f by the
  Armijo rule. Unlike a pure active-set exchange, which can cycle between active sets
  when H couples the joints strongly (it did on a Sawyer IK step, stopping 20% short of
  the optimum), every iteration decreases f, so it converges to the one optimum.

  Args:
    hessian: (n, n) H.
    gradient: (n,) g.
    lower, upper: (n,) bounds, lower <= 0 <= upper.
    iterations: most iterations (a static int).

  Returns:
    (n,) x.
  """
  objective = lambda x: 0.5 * x @ hessian @ x - gradient @ x
  alphas = 0.5 ** jnp.arange(LINE_SEARCH_STEPS, dtype=gradient.dtype)

  def stationarity(x):
    return jnp.max(jnp.abs(x - jnp.clip(x - (hessian @ x - gradient), lower, upper)))

  def unsettled(carry):
    _, residual, done = carry
    return (residual > 1e-10) & (done < iterations)

  def one_iteration(carry):
    x, residual, done = carry
    slope = hessian @ x - gradient
    margin = jnp.minimum(1e-6, residual)
    held = ((x <= lower + margin) & (slope > 0.0)) | ((x >= upper - margin) & (slope < 0.0))
    free = ~held
    both_free = free[:, None] & free[None, :]
    reduced = jnp.where(both_free, hessian, 0.0) + jnp.diag(jnp.where(free, 0.0, 1.0))
    step = jnp.where(free, jnp.linalg.solve(reduced, -jnp.where(free, slope, 0.0)), -slope)
    trials = jnp.clip(x[None, :] + alphas[:, None] * step[None, :], lower, upper)
    values = jax.vmap(objective)(trials)
    enough = values <= objective(x) + _ARMIJO * (trials - x[None, :]) @ slope
    first = jnp.argmax(enough)
    x = jnp.where(enough[first], trials[first], x)
    return x, stationarity(x), done + 1

  start = jnp.clip(jnp.zeros_like(gradient), lower, upper)
  x, _, _ = jax.lax.while_loop(unsettled, one_iteration,
                               (start, stationarity(start), jnp.array(0)))
  return x


class TaskTargets(typing.NamedTuple):
  """The world tool target of a task-space arm (a pytree of one world)."""
  pos: jnp.ndarray    # (3,)
  rot: jnp.ndarray    # (3, 3)


def apply_deltas(targets, action, tool_pos, max_translation, max_rotation, low, high):
  """TaskSpaceTargets.apply_deltas of one arm: action (>= 6,) in [-1, 1]."""
  pos = targets.pos + action[:3] * max_translation
  lag = pos - tool_pos
  distance = jnp.linalg.norm(lag)
  pos = jnp.where(distance > MAX_LAG, tool_pos + lag * (MAX_LAG / jnp.maximum(distance, 1e-12)),
                  pos)
  pos = jnp.clip(pos, low, high)
  turn = rigid.quat_to_mat(rigid.axis_angle_to_quat(action[3:6] * max_rotation))
  return TaskTargets(pos=pos, rot=turn @ targets.rot)


def joint_targets(action, low, high):
  """control_modes.joint_targets: [-1, 1] onto [low, high]."""
  return (low + high) / 2 + action * (high - low) / 2


def gripper_targets(squeeze, open_qpos, squeeze_qpos):
  """Finger targets of a gripper action (-1 open .. 1 closed), as grippers.command."""
  fraction = (jnp.clip(squeeze, -1.0, 1.0) + 1.0) / 2.0
  return open_qpos + fraction * (squeeze_qpos - open_qpos)


def gripper_opening(finger_q, open_qpos, closed_qpos):
  """1 open .. 0 closed, the mean over fingers (grippers.opening)."""
  return jnp.mean(jnp.clip((finger_q - closed_qpos) / (open_qpos - closed_qpos), 0.0, 1.0))
