"""A single arm's action in one world on the device: task-space targets, batched
differential IK, joint-position targets and the gripper command.

Task-space mode means what it means on the CPU (robots/control_modes.py,
TaskSpaceTargets): the tool target moves by `max_translation` m and turns by
`max_rotation` rad (world axes) per control step at an action of 1, is kept within
0.1 m of the measured tool and inside the arm's workspace box, and once per control
step an IK step from the measured joints gives the position actuators' targets.

The IK step solves the same weighted problem as the CPU's mink QP (robots/ik.py,
ik_qp.py): the tool's position error (cost 1) and rotation error (cost 0.5), a posture
term towards home (cost 1e-2), Levenberg-Marquardt damping 1e-3, a joint velocity
limit of VELOCITY_LIMIT rad/s over the control step and the joint ranges the CPU IK
keeps in (physical limits with the robot's IK_WORKING_RANGES). It differs in how: the
damped least-squares step is solved with the joint ranges as a box (`box_qp`: active-set
passes, each in closed form, until the active set holds, so that a joint held at its range
leaves the rest of the motion to the other joints, as the exact QP does; clipping the
unconstrained step instead stalled the tool where the shoulder met its range), then
scaled down as a whole to meet the velocity limit, where the CPU solves one QP with both
boxes exactly (DAQP); and the rotation error is the world-frame rotation vector where
mink uses the SE(3) logarithm in the tool frame. Both agree to first order;
tests/test_batch_arm.py measures the difference in tool motion. (Bounding each joint's
step by the velocity limit in the box as well, as the CPU does, brought the batched tool
to within 6 mm of the CPU's through turns, against 77 mm with the scaling, but the
batched expert, built on the scaled step, then completed 20 of 24 tables.)

The Jacobian comes from forward kinematics of the arm's kinematic chain written in
jax (`Chain`), taken from the compiled model's body, joint and site frames and
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


def tool_pose(chain_, q):
  """World position (3,) and rotation (3, 3) of the tool site at arm joints q (joints,),
  as MuJoCo's forward kinematics places it."""
  pos, rot = jnp.zeros(3, dtype=q.dtype), jnp.eye(3, dtype=q.dtype)
  for i in range(chain_.pos.shape[0]):
    pos = pos + rot @ chain_.pos[i]
    rot = rot @ chain_.rot[i]
    j = chain_.joint[i]
    if j >= 0:
      turn = _axis_rot(chain_.axis[i], q[j])
      anchor = pos + rot @ chain_.anchor[i]
      rot = rot @ turn
      pos = anchor - rot @ chain_.anchor[i]
  return pos + rot @ chain_.site_pos, rot @ chain_.site_rot


def rotation_vector(rot):
  """Axis times angle (3,) of a rotation matrix (angle in [0, pi])."""
  q = rigid.mat_to_quat(rot)
  norm = jnp.linalg.norm(q[1:])
  angle = 2.0 * jnp.arctan2(norm, q[0])
  return q[1:] * jnp.where(norm > 1e-12, angle / jnp.maximum(norm, 1e-12), 2.0)


def ik_step(chain_, q, target_pos, target_rot, home, low, high, max_step):
  """Arm joint targets after one damped-least-squares step from q towards the target.

  Args:
    chain_: the arm's Chain.
    q: (joints,) measured joints.
    target_pos, target_rot: world tool target.
    home: (joints,) posture target.
    low, high: (joints,) ranges the IK keeps in.
    max_step: largest joint change (rad) of the step (velocity limit x control step).

  Returns:
    (joints,) joint targets.
  """
  q = jnp.clip(q, low, high)
  pos, rot = tool_pose(chain_, q)
  jac_p = jax.jacfwd(lambda x: tool_pose(chain_, x)[0])(q)            # (3, n)
  jac_r_mat = jax.jacfwd(lambda x: tool_pose(chain_, x)[1])(q)        # (3, 3, n)
  spin = jnp.einsum("ijn,kj->ikn", jac_r_mat, rot)                     # dR/dq R^T
  jac_r = jnp.stack([spin[2, 1], spin[0, 2], spin[1, 0]])              # (3, n)
  jac = jnp.concatenate([jac_p, jac_r])
  error = jnp.concatenate([target_pos - pos, rotation_vector(target_rot @ rot.T)])
  weight = jnp.array([POSITION_COST] * 3 + [ORIENTATION_COST] * 3) ** 2
  n = q.shape[0]
  hessian = jac.T @ (weight[:, None] * jac) + (POSTURE_COST ** 2 + DAMPING) * jnp.eye(n)
  gradient = jac.T @ (weight * error) + POSTURE_COST ** 2 * (home - q)
  dq = box_qp(hessian, gradient, low - q, high - q)
  scale = jnp.minimum(1.0, max_step / jnp.maximum(jnp.max(jnp.abs(dq)), 1e-12))
  return jnp.clip(q + scale * dq, low, high)


# Active-set passes of box_qp, at most: a pass fixes every joint that left its box and frees
# every fixed joint the objective pulls back inside. On 300 random 7-joint problems (random
# positive definite H, g and boxes about the origin) 10 passes reached the optimum of
# scipy's L-BFGS-B in 299 (6 passes: 294; 4: 249).
BOX_QP_PASSES = 10


def box_qp(hessian, gradient, lower, upper, passes=BOX_QP_PASSES):
  """Minimises 0.5 x'Hx - g'x subject to lower <= x <= upper (H positive definite).

  Each pass solves the equality-constrained problem with the joints of the active set
  held at their bounds, then updates the set by the violated bounds and the signs of the
  gradient at the held joints (the KKT conditions), until the set stays the same (after
  one pass where no joint meets its range); the result is clipped to the box.

  Args:
    hessian: (n, n) H.
    gradient: (n,) g.
    lower, upper: (n,) bounds, lower <= upper.
    passes: most active-set passes (a static int).

  Returns:
    (n,) x.
  """
  def solve(at_lower, at_upper):
    held = at_lower | at_upper
    fixed = jnp.where(at_lower, lower, jnp.where(at_upper, upper, 0.0))
    both_free = ~held[:, None] & ~held[None, :]
    system = jnp.where(both_free, hessian, 0.0) + jnp.diag(jnp.where(held, 1.0, 0.0))
    rhs = jnp.where(held, fixed, gradient - hessian @ fixed)
    return jnp.linalg.solve(system, rhs)

  def unsettled(carry):
    _, _, changed, done = carry
    return changed & (done < passes)

  def one_pass(carry):
    at_lower, at_upper, _, done = carry
    x = solve(at_lower, at_upper)
    slope = hessian @ x - gradient      # d(objective)/dx
    free = ~(at_lower | at_upper)
    new_lower = (free & (x < lower)) | (at_lower & (slope >= 0.0))
    new_upper = (free & (x > upper)) | (at_upper & (slope <= 0.0))
    changed = jnp.any(new_lower != at_lower) | jnp.any(new_upper != at_upper)
    return new_lower, new_upper, changed, done + 1

  none = jnp.zeros(gradient.shape, dtype=bool)
  at_lower, at_upper, _, _ = jax.lax.while_loop(
      unsettled, one_pass, (none, none, jnp.array(True), jnp.array(0)))
  return jnp.clip(solve(at_lower, at_upper), lower, upper)


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
