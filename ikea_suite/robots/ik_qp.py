"""The QP of mink.build_ik for DifferentialIK's tasks, assembled with few Python objects.

mink defines the problem: a FrameTask per arm, a PostureTask, damping, a
ConfigurationLimit and a VelocityLimit. Building it through mink costs about
0.3 ms per control step in SE3 objects, per-task arrays and qpsolvers' dense
inequality form. This module reads the costs, gains and limits from those
very mink objects and assembles the same H, c and bounds from MuJoCo's C
kinematics and a handful of stacked numpy operations, the Lie-group formulas
mirroring mink's (mink/lie/se3.py, so3.py). Every mink limit here bounds one
tangent coordinate, so the inequalities are a box, which DAQP takes as simple
bounds. tests/test_ik.py checks the step against mink.build_ik + qpsolvers.
"""

import math

import daqp
import mujoco
import numpy as np


_EPS = 1e-10   # mink's small-angle threshold (mink/lie/utils.py, float64)
_INF = 1e30    # DAQP reads bounds this large as absent


_IDENTITY3 = (1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0)


def _quaternion(m0, m1, m2, m3, m4, m5, m6, m7, m8):
  """(w, x, y, z) with w >= 0 of a row-major rotation matrix (Shepperd's method)."""
  trace = m0 + m4 + m8
  if trace > 0.0:
    w = 0.5 * math.sqrt(1.0 + trace)
    f = 0.25 / w
    x, y, z = (m7 - m5) * f, (m2 - m6) * f, (m3 - m1) * f
  elif m0 > m4 and m0 > m8:
    x = 0.5 * math.sqrt(1.0 + m0 - m4 - m8)
    f = 0.25 / x
    w, y, z = (m7 - m5) * f, (m1 + m3) * f, (m2 + m6) * f
  elif m4 > m8:
    y = 0.5 * math.sqrt(1.0 + m4 - m0 - m8)
    f = 0.25 / y
    w, x, z = (m2 - m6) * f, (m1 + m3) * f, (m5 + m7) * f
  else:
    z = 0.5 * math.sqrt(1.0 + m8 - m0 - m4)
    f = 0.25 / z
    w, x, y = (m3 - m1) * f, (m2 + m6) * f, (m5 + m7) * f
  return (w, x, y, z) if w >= 0.0 else (-w, -x, -y, -z)   # as mink's SO3.log


def _mul3(a, b):
  """Product of two row-major 3x3 matrices given as 9-tuples."""
  a0, a1, a2, a3, a4, a5, a6, a7, a8 = a
  b0, b1, b2, b3, b4, b5, b6, b7, b8 = b
  return (a0 * b0 + a1 * b3 + a2 * b6, a0 * b1 + a1 * b4 + a2 * b7, a0 * b2 + a1 * b5 + a2 * b8,
          a3 * b0 + a4 * b3 + a5 * b6, a3 * b1 + a4 * b4 + a5 * b7, a3 * b2 + a4 * b5 + a5 * b8,
          a6 * b0 + a7 * b3 + a8 * b6, a6 * b1 + a7 * b4 + a8 * b7, a6 * b2 + a7 * b5 + a8 * b8)


def frame_residual(pos, mat, target_pos, target_mat):
  """mink FrameTask error and Jacobian factor of one frame, in Python floats.

  Arguments are flat float sequences (3, 9, 3, 9; matrices row-major).
  Returns (error, block, corner): error = log(T_frame^-1 T_target) as [v, omega]
  (6-tuple), and the left-Jacobian inverse of SE3 at the error, [[block, -corner],
  [0, block]] (row-major 3x3 9-tuples; corner None where it is zero). The task
  Jacobian is -[[block, -corner], [0, block]] @ J_body: mink's
  -jlog(T_target^-1 T_frame) @ J_body, as the log of an inverse is minus the log.
  Unrolled floats because at this size each numpy call costs more than its arithmetic.
  """
  r0, r1, r2, r3, r4, r5, r6, r7, r8 = mat
  s0, s1, s2, s3, s4, s5, s6, s7, s8 = target_mat
  dx, dy, dz = target_pos[0] - pos[0], target_pos[1] - pos[1], target_pos[2] - pos[2]
  tx, ty, tz = r0 * dx + r3 * dy + r6 * dz, r1 * dx + r4 * dy + r7 * dz, r2 * dx + r5 * dy + r8 * dz
  qw, qx, qy, qz = _quaternion(   # of mat^T target_mat
      r0 * s0 + r3 * s3 + r6 * s6, r0 * s1 + r3 * s4 + r6 * s7, r0 * s2 + r3 * s5 + r6 * s8,
      r1 * s0 + r4 * s3 + r7 * s6, r1 * s1 + r4 * s4 + r7 * s7, r1 * s2 + r4 * s5 + r7 * s8,
      r2 * s0 + r5 * s3 + r8 * s6, r2 * s1 + r5 * s4 + r8 * s7, r2 * s2 + r5 * s5 + r8 * s8)
  norm = math.sqrt(qx * qx + qy * qy + qz * qz)
  scale = 0.0 if norm < _EPS else 2.0 * math.atan2(norm, qw) / norm
  wx, wy, wz = qx * scale, qy * scale, qz * scale               # SO3 log
  t2 = wx * wx + wy * wy + wz * wz
  theta = math.sqrt(t2)
  if t2 < _EPS:
    coeff = 1.0 / 12.0
  else:
    half = 0.5 * theta
    coeff = (1.0 - half * math.cos(half) / math.sin(half)) / t2
  # v = V^-1 t, V^-1 = I - skew(w) / 2 + coeff skew(w)^2 (mink's SE3.log).
  ax, ay, az = wy * tz - wz * ty, wz * tx - wx * tz, wx * ty - wy * tx
  bx, by, bz = wy * az - wz * ay, wz * ax - wx * az, wx * ay - wy * ax
  vx, vy, vz = tx - 0.5 * ax + coeff * bx, ty - 0.5 * ay + coeff * by, tz - 0.5 * az + coeff * bz
  error = (vx, vy, vz, wx, wy, wz)
  if t2 < _EPS:
    return error, _IDENTITY3, None
  sin, cos = math.sin(theta), math.cos(theta)
  beta = (1.0 - theta * sin / (2.0 * (1.0 - cos))) / t2           # mink's SO3.ljacinv
  b = (theta - sin) / (t2 * theta)                                 # mink's _getQ B, C, D
  c = (1.0 - 0.5 * t2 - cos) / (t2 * t2)
  d = (2.0 * theta - 3.0 * sin + theta * cos) / (2.0 * t2 * t2 * theta)
  # SO3.ljacinv = (1 - beta t2) I + beta w w^T - skew(w) / 2.
  e = 1.0 - beta * t2
  so3 = (e + beta * wx * wx, beta * wx * wy + 0.5 * wz, beta * wx * wz - 0.5 * wy,
         beta * wy * wx - 0.5 * wz, e + beta * wy * wy, beta * wy * wz + 0.5 * wx,
         beta * wz * wx + 0.5 * wy, beta * wz * wy - 0.5 * wx, e + beta * wz * wz)
  # _getQ's skew products in closed form (V = skew(v), W = skew(w), s = v.w, u = v x w):
  # VW + WV = v w^T + w v^T - 2 s I, WVW = -s W, VWW - (VWW)^T = u w^T - w u^T - 2 t2 V,
  # WVWW + WWVW = -2 s (w w^T - t2 I); so Q = g w^T + w h^T + skew(k) + diag I with:
  sv = vx * wx + vy * wy + vz * wz
  ux, uy, uz = vy * wz - vz * wy, vz * wx - vx * wz, vx * wy - vy * wx
  ds = 2.0 * d * sv
  gx, gy, gz = b * vx - c * ux - ds * wx, b * vy - c * uy - ds * wy, b * vz - c * uz - ds * wz
  hx, hy, hz = b * vx + c * ux, b * vy + c * uy, b * vz + c * uz
  alpha, gamma = 0.5 + 2.0 * c * t2, -(b + 3.0 * c) * sv
  kx, ky, kz = alpha * vx + gamma * wx, alpha * vy + gamma * wy, alpha * vz + gamma * wz
  diag = -2.0 * b * sv + ds * t2
  q = (gx * wx + wx * hx + diag, gx * wy + wx * hy - kz, gx * wz + wx * hz + ky,
       gy * wx + wy * hx + kz, gy * wy + wy * hy + diag, gy * wz + wy * hz - kx,
       gz * wx + wz * hx - ky, gz * wy + wz * hy + kx, gz * wz + wz * hz + diag)
  return error, so3, _mul3(so3, _mul3(q, so3))


def frame_rows(pos, mat, target_pos, target_mat, cost):
  """One frame task's share of the QP: (error, block), in Python floats.

  error: frame_residual's (6-tuple). block: cost * [[B, -C], [0, B]] @ diag(R^T, R^T) as a
  row-major 6x6 36-tuple, with B, C frame_residual's factor and R = `mat` (the site's
  rotation, 9 floats row-major): multiplied by mj_jacSite's world-aligned Jacobian it gives
  the site's rows of DirectQP's w, the Jacobian turned into the site frame (mink's body
  Jacobian) on the way. `cost`: the task's six costs.
  """
  m = mat
  error, block, corner = frame_residual(pos, m, target_pos, target_mat)
  t0, t1, t2, t3, t4, t5, t6, t7, t8 = _mul3(
      block, (m[0], m[3], m[6], m[1], m[4], m[7], m[2], m[5], m[8]))
  s0, s1, s2, s3, s4, s5, s6, s7, s8 = (0.0,) * 9 if corner is None else _mul3(
      corner, (-m[0], -m[3], -m[6], -m[1], -m[4], -m[7], -m[2], -m[5], -m[8]))
  c0, c1, c2, c3, c4, c5 = cost
  return error, (c0 * t0, c0 * t1, c0 * t2, c0 * s0, c0 * s1, c0 * s2,
                 c1 * t3, c1 * t4, c1 * t5, c1 * s3, c1 * s4, c1 * s5,
                 c2 * t6, c2 * t7, c2 * t8, c2 * s6, c2 * s7, c2 * s8,
                 0.0, 0.0, 0.0, c3 * t0, c3 * t1, c3 * t2,
                 0.0, 0.0, 0.0, c4 * t3, c4 * t4, c4 * t5,
                 0.0, 0.0, 0.0, c5 * t6, c5 * t7, c5 * t8)


class DirectQP:
  """mink.build_ik's QP for frame tasks on sites, a posture task and box limits, solved by DAQP.

  Needs hinge and slide joints only (tangent and configuration spaces coincide).
  Costs, gains and limits are read from the mink objects at construction.
  """

  def __init__(self, model, site_ids, frame_tasks, posture, configuration_limit,
               velocity_limit, damping):
    if model.nq != model.nv:
      raise ValueError("DirectQP needs hinge and slide joints only")
    if any(t.lm_damping for t in frame_tasks) or posture.lm_damping:
      raise ValueError("DirectQP does not implement Levenberg-Marquardt task damping")
    self._model, self._data = model, mujoco.MjData(model)
    self._sites = [int(s) for s in site_ids]
    nv = model.nv
    self._jac = np.zeros((len(self._sites), 6, nv))
    # Views fetched once (each MjData attribute read builds a new numpy view): the
    # positional and rotational Jacobian rows of each site, and what assemble reads.
    self._jac_rows = [(self._jac[i, :3], self._jac[i, 3:]) for i in range(len(self._sites))]
    data = self._data
    self._qpos, self._site_xpos, self._site_xmat = data.qpos, data.site_xpos, data.site_xmat
    cost = np.array([t.cost for t in frame_tasks], dtype=float)              # (arms, 6)
    self._cost_rows = cost.tolist()
    # mink's weighted error is cost * (-gain * error).
    self._error_weight = -(cost * np.array([[t.gain] for t in frame_tasks])).reshape(-1)
    # The posture task's Jacobian is the identity: cost^2 on H's diagonal, with the damping.
    self._diagonal = np.diag(posture.cost * posture.cost + damping)
    self._posture_weight = posture.cost * posture.cost * posture.gain
    self._posture_offset = None   # posture weight * target, from set_posture_target
    limit = configuration_limit
    self._gain_upper = np.full(nv, np.inf)
    self._gain_lower = np.full(nv, -np.inf)
    self._gain_upper[limit.indices] = limit.gain * limit.upper[limit.indices]   # nq == nv
    self._gain_lower[limit.indices] = limit.gain * limit.lower[limit.indices]
    self._limit_gain = limit.gain
    self._speed = np.full(nv, np.inf)
    self._speed[velocity_limit.indices] = velocity_limit.limit
    self._caps = {}   # (dt, velocity_limited) -> +-speed bound per coordinate, capped at _INF
    self._no_rows = np.zeros((0, nv))
    self._sense = np.zeros(nv, dtype=np.intc)
    # What every step writes again: w, as (sites, 6, nv) and as its rows, and the weighted
    # errors (see _rows).
    self._w = np.zeros((len(self._sites), 6, nv))
    self._w_rows = self._w.reshape(-1, nv)
    self._weighted = np.zeros(6 * len(self._sites))

  def set_posture_target(self, q):
    self._posture_offset = self._posture_weight * np.asarray(q, dtype=float)

  def assemble(self, q, targets, dt, velocity_limited=True):
    """(H, c, lower, upper) of the QP at q (within the limits); see `solve`."""
    if self._posture_offset is None:
      raise ValueError("the posture target is not set (DifferentialIK.set_posture)")
    model, data = self._model, self._data
    self._qpos[:] = q
    mujoco.mj_kinematics(model, data)
    mujoco.mj_comPos(model, data)   # mj_jacSite reads the com-based frames
    for site, (jacp, jacr) in zip(self._sites, self._jac_rows):
      mujoco.mj_jacSite(model, data, jacp, jacr, site)
    # w is minus mink's weighted Jacobian W: H = W^T W = w^T w and
    # c = -(weighted error) @ W = (weighted error) @ w.
    w, weighted = self._rows(targets)
    h = w.T @ w
    c = weighted @ w
    h += self._diagonal
    c += self._posture_weight * q
    c -= self._posture_offset
    # mink's ConfigurationLimit and VelocityLimit rows, intersected per coordinate.
    cap, floor = self._cap(dt, velocity_limited)
    gain_q = self._limit_gain * q
    upper = np.minimum(self._gain_upper - gain_q, cap)
    lower = np.maximum(self._gain_lower - gain_q, floor)
    return h, c, lower, upper

  def _cap(self, dt, velocity_limited):
    """(cap, floor): mink's VelocityLimit as +-bounds on the step, capped at _INF."""
    key = (dt, velocity_limited)
    if key not in self._caps:
      speed = self._speed * dt if velocity_limited else np.full(self._model.nv, np.inf)
      cap = np.minimum(speed, _INF)
      self._caps[key] = cap, -cap
    return self._caps[key]

  def _rows(self, targets):
    """(w, weighted errors) of the frame tasks, by frame_rows in Python floats, in arrays
    the next call overwrites."""
    errors, blocks = [], []
    xpos, xmat = self._site_xpos, self._site_xmat
    for site, (pos, rot), cost in zip(self._sites, targets, self._cost_rows):
      if isinstance(pos, np.ndarray):
        pos = pos.tolist()
      if isinstance(rot, np.ndarray) or len(rot) != 9:
        rot = np.asarray(rot, dtype=float).reshape(9).tolist()
      error, block = frame_rows(xpos[site].tolist(), xmat[site].tolist(), pos, rot, cost)
      errors += error
      blocks.append(block)
    np.matmul(np.array(blocks).reshape(-1, 6, 6), self._jac, out=self._w)
    np.multiply(self._error_weight, errors, out=self._weighted)
    return self._w_rows, self._weighted

  def solve(self, q, targets, dt, velocity_limited=True):
    """The step displacement from q (within the limits) towards `targets`, or None.

    targets: per frame task, (position (3,), rotation (3, 3) or 9 floats row-major)
    in the model's frame.
    """
    h, c, lower, upper = self.assemble(q, targets, dt, velocity_limited)
    x, _, exitflag, _ = daqp.solve(h, c, self._no_rows, upper, lower, self._sense)
    return x if exitflag > 0 else None
