/* Compiled twins of the task-space control step's small arithmetic:
 *
 *   frame_rows    ik_qp.frame_rows (frame_residual, _quaternion, _mul3, the cost products);
 *   qp_finish     the element-wise end of ik_qp.DirectQP.assemble (H's diagonal, c's
 *                 posture terms, the bounds), which numpy spends a call per operation on;
 *   delta_target  one arm's step of control_modes.TaskSpaceTargets.apply_deltas (the
 *                 position and _axis_angle_rows; the rotation product stays numpy's);
 *   in_frame      one arm's target in TaskSpaceTargets.in_frame.
 *
 * The same floating-point operations in the same order as the Python and numpy, so the
 * results agree to the bit: C doubles round as Python floats and numpy's element-wise
 * operations do, the math functions are the C library's that Python's math module calls,
 * np.minimum/np.maximum's choice (NaN first, else the second operand on a tie) is kept, and
 * setup.py builds this with -ffp-contract=off so that no multiply-add is fused.
 * tests/test_ik.py compares each with its Python twin.
 */
#define PY_SSIZE_T_CLEAN
#include <Python.h>
#include <math.h>
#include <string.h>

#define EPS 1e-10 /* mink's small-angle threshold, as ik_qp._EPS */

/* 1 with a TypeError naming the signature when nargs is not `expected`, else 0. */
static int wrong_nargs(Py_ssize_t nargs, Py_ssize_t expected, const char *signature) {
  if (nargs == expected) return 0;
  PyErr_Format(PyExc_TypeError, "%s takes %zd arguments", signature, expected);
  return 1;
}

/* A C-contiguous buffer of `count` doubles (writable if asked); 0 with an exception if not. */
static int get_doubles(PyObject *obj, Py_buffer *view, Py_ssize_t count, int writable,
                       const char *name) {
  int flags = PyBUF_C_CONTIGUOUS | PyBUF_FORMAT | (writable ? PyBUF_WRITABLE : 0);
  if (PyObject_GetBuffer(obj, view, flags) != 0) return 0;
  const char *format = view->format;
  if (format[0] == '<' || format[0] == '=' || format[0] == '@') format++;
  if (view->itemsize != sizeof(double) || strcmp(format, "d") != 0 ||
      view->len != count * (Py_ssize_t)sizeof(double)) {
    PyErr_Format(PyExc_TypeError, "%s must be %zd contiguous float64 numbers", name, count);
    PyBuffer_Release(view);
    return 0;
  }
  return 1;
}

/* Reads `count` floats from a contiguous float64 array, or else from a sequence of numbers
 * (other arrays included); 0 on error. */
static int read_floats(PyObject *obj, double *out, Py_ssize_t count, const char *name) {
  if (PyObject_CheckBuffer(obj)) {
    Py_buffer view;
    if (get_doubles(obj, &view, count, 0, name)) {
      memcpy(out, view.buf, count * sizeof(double));
      PyBuffer_Release(&view);
      return 1;
    }
    PyErr_Clear();   /* not contiguous float64: read it as a sequence */
  }
  PyObject *fast = PySequence_Fast(obj, name);
  if (fast == NULL) return 0;
  if (PySequence_Fast_GET_SIZE(fast) != count) {
    PyErr_Format(PyExc_ValueError, "%s must hold %zd numbers", name, count);
    Py_DECREF(fast);
    return 0;
  }
  PyObject **items = PySequence_Fast_ITEMS(fast);
  for (Py_ssize_t i = 0; i < count; i++) {
    out[i] = PyFloat_AsDouble(items[i]);
    if (out[i] == -1.0 && PyErr_Occurred()) {
      Py_DECREF(fast);
      return 0;
    }
  }
  Py_DECREF(fast);
  return 1;
}

/* ik_qp._quaternion: (w, x, y, z), w >= 0, of a row-major rotation matrix. */
static void quaternion(const double *m, double *q) {
  double w, x, y, z, f;
  double trace = m[0] + m[4] + m[8];
  if (trace > 0.0) {
    w = 0.5 * sqrt(1.0 + trace);
    f = 0.25 / w;
    x = (m[7] - m[5]) * f; y = (m[2] - m[6]) * f; z = (m[3] - m[1]) * f;
  } else if (m[0] > m[4] && m[0] > m[8]) {
    x = 0.5 * sqrt(1.0 + m[0] - m[4] - m[8]);
    f = 0.25 / x;
    w = (m[7] - m[5]) * f; y = (m[1] + m[3]) * f; z = (m[2] + m[6]) * f;
  } else if (m[4] > m[8]) {
    y = 0.5 * sqrt(1.0 + m[4] - m[0] - m[8]);
    f = 0.25 / y;
    w = (m[2] - m[6]) * f; x = (m[1] + m[3]) * f; z = (m[5] + m[7]) * f;
  } else {
    z = 0.5 * sqrt(1.0 + m[8] - m[0] - m[4]);
    f = 0.25 / z;
    w = (m[3] - m[1]) * f; x = (m[2] + m[6]) * f; y = (m[5] + m[7]) * f;
  }
  if (w >= 0.0) {
    q[0] = w; q[1] = x; q[2] = y; q[3] = z;
  } else {
    q[0] = -w; q[1] = -x; q[2] = -y; q[3] = -z;
  }
}

/* ik_qp._mul3: out = a @ b, row-major 3x3. */
static void mul3(const double *a, const double *b, double *out) {
  out[0] = a[0] * b[0] + a[1] * b[3] + a[2] * b[6];
  out[1] = a[0] * b[1] + a[1] * b[4] + a[2] * b[7];
  out[2] = a[0] * b[2] + a[1] * b[5] + a[2] * b[8];
  out[3] = a[3] * b[0] + a[4] * b[3] + a[5] * b[6];
  out[4] = a[3] * b[1] + a[4] * b[4] + a[5] * b[7];
  out[5] = a[3] * b[2] + a[4] * b[5] + a[5] * b[8];
  out[6] = a[6] * b[0] + a[7] * b[3] + a[8] * b[6];
  out[7] = a[6] * b[1] + a[7] * b[4] + a[8] * b[7];
  out[8] = a[6] * b[2] + a[7] * b[5] + a[8] * b[8];
}

/* ik_qp.frame_residual: error (6) and factor blocks so3 (9) and corner (9); returns 0
 * where the corner is zero (the Python's None). */
static int frame_residual(const double *pos, const double *r, const double *target_pos,
                          const double *s, double *error, double *so3, double *corner) {
  double dx = target_pos[0] - pos[0], dy = target_pos[1] - pos[1], dz = target_pos[2] - pos[2];
  double tx = r[0] * dx + r[3] * dy + r[6] * dz;
  double ty = r[1] * dx + r[4] * dy + r[7] * dz;
  double tz = r[2] * dx + r[5] * dy + r[8] * dz;
  double rel[9] = {
      r[0] * s[0] + r[3] * s[3] + r[6] * s[6], r[0] * s[1] + r[3] * s[4] + r[6] * s[7],
      r[0] * s[2] + r[3] * s[5] + r[6] * s[8], r[1] * s[0] + r[4] * s[3] + r[7] * s[6],
      r[1] * s[1] + r[4] * s[4] + r[7] * s[7], r[1] * s[2] + r[4] * s[5] + r[7] * s[8],
      r[2] * s[0] + r[5] * s[3] + r[8] * s[6], r[2] * s[1] + r[5] * s[4] + r[8] * s[7],
      r[2] * s[2] + r[5] * s[5] + r[8] * s[8]};
  double q[4];
  quaternion(rel, q);
  double qw = q[0], qx = q[1], qy = q[2], qz = q[3];
  double norm = sqrt(qx * qx + qy * qy + qz * qz);
  double scale = norm < EPS ? 0.0 : 2.0 * atan2(norm, qw) / norm;
  double wx = qx * scale, wy = qy * scale, wz = qz * scale;
  double t2 = wx * wx + wy * wy + wz * wz;
  double theta = sqrt(t2);
  double coeff;
  if (t2 < EPS) {
    coeff = 1.0 / 12.0;
  } else {
    double half = 0.5 * theta;
    coeff = (1.0 - half * cos(half) / sin(half)) / t2;
  }
  double ax = wy * tz - wz * ty, ay = wz * tx - wx * tz, az = wx * ty - wy * tx;
  double bx = wy * az - wz * ay, by = wz * ax - wx * az, bz = wx * ay - wy * ax;
  double vx = tx - 0.5 * ax + coeff * bx;
  double vy = ty - 0.5 * ay + coeff * by;
  double vz = tz - 0.5 * az + coeff * bz;
  error[0] = vx; error[1] = vy; error[2] = vz; error[3] = wx; error[4] = wy; error[5] = wz;
  if (t2 < EPS) {
    static const double identity[9] = {1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0};
    for (int i = 0; i < 9; i++) so3[i] = identity[i];
    return 0;
  }
  double sn = sin(theta), cs = cos(theta);
  double beta = (1.0 - theta * sn / (2.0 * (1.0 - cs))) / t2;
  double b = (theta - sn) / (t2 * theta);
  double c = (1.0 - 0.5 * t2 - cs) / (t2 * t2);
  double d = (2.0 * theta - 3.0 * sn + theta * cs) / (2.0 * t2 * t2 * theta);
  double e = 1.0 - beta * t2;
  so3[0] = e + beta * wx * wx;   so3[1] = beta * wx * wy + 0.5 * wz; so3[2] = beta * wx * wz - 0.5 * wy;
  so3[3] = beta * wy * wx - 0.5 * wz; so3[4] = e + beta * wy * wy;   so3[5] = beta * wy * wz + 0.5 * wx;
  so3[6] = beta * wz * wx + 0.5 * wy; so3[7] = beta * wz * wy - 0.5 * wx; so3[8] = e + beta * wz * wz;
  double sv = vx * wx + vy * wy + vz * wz;
  double ux = vy * wz - vz * wy, uy = vz * wx - vx * wz, uz = vx * wy - vy * wx;
  double ds = 2.0 * d * sv;
  double gx = b * vx - c * ux - ds * wx, gy = b * vy - c * uy - ds * wy, gz = b * vz - c * uz - ds * wz;
  double hx = b * vx + c * ux, hy = b * vy + c * uy, hz = b * vz + c * uz;
  double alpha = 0.5 + 2.0 * c * t2, gamma = -(b + 3.0 * c) * sv;
  double kx = alpha * vx + gamma * wx, ky = alpha * vy + gamma * wy, kz = alpha * vz + gamma * wz;
  double diag = -2.0 * b * sv + ds * t2;
  double qm[9] = {gx * wx + wx * hx + diag, gx * wy + wx * hy - kz, gx * wz + wx * hz + ky,
                  gy * wx + wy * hx + kz, gy * wy + wy * hy + diag, gy * wz + wy * hz - kx,
                  gz * wx + wz * hx - ky, gz * wy + wz * hy + kx, gz * wz + wz * hz + diag};
  double inner[9];
  mul3(qm, so3, inner);
  mul3(so3, inner, corner);
  return 1;
}

/* frame_rows' arithmetic on (pos, mat, target_pos, target_mat, cost) read from args[0..4]:
 * error (6) and block (36, row-major 6x6); 0 with an exception on bad arguments. */
static int rows(PyObject *const *args, double *error, double *block) {
  double pos[3], m[9], target_pos[3], target_mat[9], cost[6];
  if (!read_floats(args[0], pos, 3, "pos") || !read_floats(args[1], m, 9, "mat") ||
      !read_floats(args[2], target_pos, 3, "target_pos") ||
      !read_floats(args[3], target_mat, 9, "target_mat") || !read_floats(args[4], cost, 6, "cost"))
    return 0;
  double so3[9], corner[9];
  int has_corner = frame_residual(pos, m, target_pos, target_mat, error, so3, corner);
  double rt[9] = {m[0], m[3], m[6], m[1], m[4], m[7], m[2], m[5], m[8]};
  double t[9], s[9];
  mul3(so3, rt, t);
  if (has_corner) {
    double neg[9] = {-m[0], -m[3], -m[6], -m[1], -m[4], -m[7], -m[2], -m[5], -m[8]};
    mul3(corner, neg, s);
  } else {
    for (int i = 0; i < 9; i++) s[i] = 0.0;
  }
  for (int row = 0; row < 3; row++) {   /* [cost * B R^T, cost * -C R^T] */
    for (int col = 0; col < 3; col++) {
      block[6 * row + col] = cost[row] * t[3 * row + col];
      block[6 * row + 3 + col] = cost[row] * s[3 * row + col];
    }
  }
  for (int row = 3; row < 6; row++) {   /* [0, cost * B R^T] */
    for (int col = 0; col < 3; col++) {
      block[6 * row + col] = 0.0;
      block[6 * row + 3 + col] = cost[row] * t[3 * (row - 3) + col];
    }
  }
  return 1;
}

static PyObject *frame_rows(PyObject *self, PyObject *const *args, Py_ssize_t nargs) {
  (void)self;
  if (wrong_nargs(nargs, 5, "frame_rows(pos, mat, target_pos, target_mat, cost)")) return NULL;
  double error[6], block[36];
  if (!rows(args, error, block)) return NULL;
  PyObject *error_tuple = PyTuple_New(6), *block_tuple = PyTuple_New(36);
  if (error_tuple == NULL || block_tuple == NULL) goto fail;
  for (int i = 0; i < 6; i++) {
    PyObject *value = PyFloat_FromDouble(error[i]);
    if (value == NULL) goto fail;
    PyTuple_SET_ITEM(error_tuple, i, value);
  }
  for (int i = 0; i < 36; i++) {
    PyObject *value = PyFloat_FromDouble(block[i]);
    if (value == NULL) goto fail;
    PyTuple_SET_ITEM(block_tuple, i, value);
  }
  PyObject *result = PyTuple_Pack(2, error_tuple, block_tuple);
  Py_DECREF(error_tuple);
  Py_DECREF(block_tuple);
  return result;
fail:
  Py_XDECREF(error_tuple);
  Py_XDECREF(block_tuple);
  return NULL;
}

/* np.minimum(a, b) and np.maximum(a, b) on one pair of doubles. */
static double np_min(double a, double b) { return (isnan(a) || a < b) ? a : b; }
static double np_max(double a, double b) { return (isnan(a) || a > b) ? a : b; }

static PyObject *qp_finish(PyObject *self, PyObject *const *args, Py_ssize_t nargs) {
  (void)self;
  if (wrong_nargs(nargs, 13, "qp_finish(h, c, q, diagonal, posture_weight, posture_offset, "
                             "limit_gain, gain_upper, gain_lower, cap, floor, upper, lower)"))
    return NULL;
  double limit_gain = PyFloat_AsDouble(args[6]);
  if (limit_gain == -1.0 && PyErr_Occurred()) return NULL;
  Py_buffer c_view;   /* c's length sets n */
  if (PyObject_GetBuffer(args[1], &c_view, PyBUF_C_CONTIGUOUS) != 0) return NULL;
  Py_ssize_t n = c_view.len / (Py_ssize_t)sizeof(double);
  PyBuffer_Release(&c_view);
  /* Every argument but limit_gain (6) is an array. */
  static const int slot[12] = {0, 1, 2, 3, 4, 5, 7, 8, 9, 10, 11, 12};
  static const char *names[12] = {"h", "c", "q", "diagonal", "posture_weight", "posture_offset",
                                  "gain_upper", "gain_lower", "cap", "floor", "upper", "lower"};
  const int writable[12] = {1, 1, 0, 0, 0, 0, 0, 0, 0, 0, 1, 1};
  const Py_ssize_t counts[12] = {n * n, n, n, n * n, n, n, n, n, n, n, n, n};
  Py_buffer views[12];
  double *v[12];
  int got = 0;
  for (; got < 12; got++) {
    if (!get_doubles(args[slot[got]], &views[got], counts[got], writable[got], names[got])) break;
    v[got] = (double *)views[got].buf;
  }
  if (got == 12) {
    double *h = v[0], *c = v[1], *q = v[2], *diagonal = v[3], *posture_weight = v[4];
    double *offset = v[5], *gain_upper = v[6], *gain_lower = v[7], *cap = v[8], *floor = v[9];
    double *upper = v[10], *lower = v[11];
    for (Py_ssize_t i = 0; i < n * n; i++) h[i] = h[i] + diagonal[i];   /* h += diagonal */
    for (Py_ssize_t i = 0; i < n; i++) {
      c[i] = c[i] + posture_weight[i] * q[i];   /* c += posture_weight * q */
      c[i] = c[i] - offset[i];               /* c -= posture_offset */
      double gain_q = limit_gain * q[i];
      upper[i] = np_min(gain_upper[i] - gain_q, cap[i]);
      lower[i] = np_max(gain_lower[i] - gain_q, floor[i]);
    }
  }
  for (int i = 0; i < got; i++) PyBuffer_Release(&views[i]);
  if (got != 12) return NULL;
  Py_RETURN_NONE;
}

/* frame_rows(pos, mat, target_pos, target_mat, cost) written into arrays: block into
 * block_out (36 float64) and weight * error (numpy's element-wise product) into
 * weighted_out (6 float64). */
static PyObject *frame_rows_into(PyObject *self, PyObject *const *args, Py_ssize_t nargs) {
  (void)self;
  if (wrong_nargs(nargs, 8, "frame_rows_into(pos, mat, target_pos, target_mat, cost, weight, "
                            "block_out, weighted_out)"))
    return NULL;
  double error[6], block[36], weight[6];
  if (!rows(args, error, block) || !read_floats(args[5], weight, 6, "weight")) return NULL;
  Py_buffer block_view, weighted_view;
  if (!get_doubles(args[6], &block_view, 36, 1, "block_out")) return NULL;
  if (!get_doubles(args[7], &weighted_view, 6, 1, "weighted_out")) {
    PyBuffer_Release(&block_view);
    return NULL;
  }
  memcpy(block_view.buf, block, sizeof(block));
  double *weighted = (double *)weighted_view.buf;
  for (int i = 0; i < 6; i++) weighted[i] = weight[i] * error[i];
  PyBuffer_Release(&block_view);
  PyBuffer_Release(&weighted_view);
  Py_RETURN_NONE;
}

/* Python's min(max(value, low), high). */
static double py_clamp(double value, double low, double high) {
  double x = low > value ? low : value;
  return high < x ? high : x;
}

static PyObject *float_list(const double *values, int count) {
  PyObject *list = PyList_New(count);
  if (list == NULL) return NULL;
  for (int i = 0; i < count; i++) {
    PyObject *value = PyFloat_FromDouble(values[i]);
    if (value == NULL) {
      Py_DECREF(list);
      return NULL;
    }
    PyList_SET_ITEM(list, i, value);
  }
  return list;
}

/* delta_target(pos, move, tcp, step, turn, max_lag, low, high, turn_out) -> (new pos list,
 * turned): one arm of TaskSpaceTargets.apply_deltas. Where the move turns, the turn's
 * rotation matrix (_axis_angle_rows) is written into turn_out (9 float64). */
static PyObject *delta_target(PyObject *self, PyObject *const *args, Py_ssize_t nargs) {
  (void)self;
  if (wrong_nargs(nargs, 9, "delta_target(pos, move, tcp, step, turn, max_lag, low, high, "
                            "turn_out)"))
    return NULL;
  double p[3], move[6], tcp[3], low[3], high[3];
  if (!read_floats(args[0], p, 3, "pos") || !read_floats(args[1], move, 6, "move") ||
      !read_floats(args[2], tcp, 3, "tcp") || !read_floats(args[6], low, 3, "low") ||
      !read_floats(args[7], high, 3, "high"))
    return NULL;
  double step = PyFloat_AsDouble(args[3]), turn = PyFloat_AsDouble(args[4]);
  double max_lag = PyFloat_AsDouble(args[5]);
  if (PyErr_Occurred()) return NULL;
  double target[3] = {p[0] + move[0] * step, p[1] + move[1] * step, p[2] + move[2] * step};
  double lag[3] = {target[0] - tcp[0], target[1] - tcp[1], target[2] - tcp[2]};
  double distance = sqrt(lag[0] * lag[0] + lag[1] * lag[1] + lag[2] * lag[2]);
  if (distance > max_lag) {
    for (int k = 0; k < 3; k++) target[k] = tcp[k] + lag[k] * (max_lag / distance);
  }
  double pos[3];
  for (int k = 0; k < 3; k++) pos[k] = py_clamp(target[k], low[k], high[k]);
  double x = move[3] * turn, y = move[4] * turn, z = move[5] * turn;
  int turned = x != 0.0 || y != 0.0 || z != 0.0;   /* Python's `x or y or z`: NaN turns */
  if (turned) {
    Py_buffer out;
    if (!get_doubles(args[8], &out, 9, 1, "turn_out")) return NULL;
    double *r = (double *)out.buf;
    double angle = sqrt(x * x + y * y + z * z);
    if (angle <= 1e-12) {
      static const double identity[9] = {1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0};
      memcpy(r, identity, sizeof(identity));
    } else {
      double s = sin(angle * 0.5) / angle;
      double w = cos(angle * 0.5);
      x = x * s; y = y * s; z = z * s;
      double ww = w * w, xx = x * x, yy = y * y, zz = z * z;
      double wx = w * x, wy = w * y, wz = w * z, xy = x * y, xz = x * z, yz = y * z;
      r[0] = ww + xx - yy - zz; r[1] = 2 * (xy - wz);      r[2] = 2 * (xz + wy);
      r[3] = 2 * (xy + wz);     r[4] = ww - xx + yy - zz;  r[5] = 2 * (yz - wx);
      r[6] = 2 * (xz - wy);     r[7] = 2 * (yz + wx);      r[8] = ww - xx - yy + zz;
    }
    PyBuffer_Release(&out);
  }
  PyObject *pos_list = float_list(pos, 3);
  if (pos_list == NULL) return NULL;
  PyObject *result = Py_BuildValue("(NO)", pos_list, turned ? Py_True : Py_False);
  return result;
}

/* in_frame(pos, rot, origin, rotation) -> (position list, rotation list): one arm of
 * TaskSpaceTargets.in_frame (pos 3 and rot 9 in the world, into the frame at origin turned
 * by rotation, row-major). */
static PyObject *in_frame(PyObject *self, PyObject *const *args, Py_ssize_t nargs) {
  (void)self;
  if (wrong_nargs(nargs, 4, "in_frame(pos, rot, origin, rotation)")) return NULL;
  double p[3], m[9], o[3], r[9];
  if (!read_floats(args[0], p, 3, "pos") || !read_floats(args[1], m, 9, "rot") ||
      !read_floats(args[2], o, 3, "origin") || !read_floats(args[3], r, 9, "rotation"))
    return NULL;
  double x = p[0] - o[0], y = p[1] - o[1], z = p[2] - o[2];
  double pos[3] = {r[0] * x + r[3] * y + r[6] * z, r[1] * x + r[4] * y + r[7] * z,
                   r[2] * x + r[5] * y + r[8] * z};
  double rot[9] = {r[0] * m[0] + r[3] * m[3] + r[6] * m[6], r[0] * m[1] + r[3] * m[4] + r[6] * m[7],
                   r[0] * m[2] + r[3] * m[5] + r[6] * m[8], r[1] * m[0] + r[4] * m[3] + r[7] * m[6],
                   r[1] * m[1] + r[4] * m[4] + r[7] * m[7], r[1] * m[2] + r[4] * m[5] + r[7] * m[8],
                   r[2] * m[0] + r[5] * m[3] + r[8] * m[6], r[2] * m[1] + r[5] * m[4] + r[8] * m[7],
                   r[2] * m[2] + r[5] * m[5] + r[8] * m[8]};
  PyObject *pos_list = float_list(pos, 3);
  if (pos_list == NULL) return NULL;
  PyObject *rot_list = float_list(rot, 9);
  if (rot_list == NULL) {
    Py_DECREF(pos_list);
    return NULL;
  }
  return Py_BuildValue("(NN)", pos_list, rot_list);
}

static PyMethodDef methods[] = {
    {"frame_rows", (PyCFunction)(void (*)(void))frame_rows, METH_FASTCALL,
     "frame_rows(pos, mat, target_pos, target_mat, cost) -> (error, block): "
     "ikea_suite.robots.ik_qp.frame_rows, compiled."},
    {"frame_rows_into", (PyCFunction)(void (*)(void))frame_rows_into, METH_FASTCALL,
     "frame_rows_into(pos, mat, target_pos, target_mat, cost, weight, block_out, "
     "weighted_out): frame_rows' block into block_out and weight * error into "
     "weighted_out."},
    {"delta_target", (PyCFunction)(void (*)(void))delta_target, METH_FASTCALL,
     "delta_target(pos, move, tcp, step, turn, max_lag, low, high, turn_out) -> (pos, "
     "turned): one arm of control_modes.TaskSpaceTargets.apply_deltas."},
    {"in_frame", (PyCFunction)(void (*)(void))in_frame, METH_FASTCALL,
     "in_frame(pos, rot, origin, rotation) -> (position, rotation): one arm of "
     "control_modes.TaskSpaceTargets.in_frame."},
    {"qp_finish", (PyCFunction)(void (*)(void))qp_finish, METH_FASTCALL,
     "qp_finish(h, c, q, diagonal, posture_weight, posture_offset, limit_gain, gain_upper, "
     "gain_lower, cap, floor, upper, lower): the element-wise end of DirectQP.assemble, "
     "in place on h and c, into upper and lower."},
    {NULL, NULL, 0, NULL}};

static struct PyModuleDef module = {PyModuleDef_HEAD_INIT, "_ik_kernels",
                                    "Compiled twins of pieces of ik_qp.", -1, methods,
                                    NULL, NULL, NULL, NULL};

PyMODINIT_FUNC PyInit__ik_kernels(void) { return PyModule_Create(&module); }
