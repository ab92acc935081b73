/* Compiled twins of the task-space control step's small arithmetic:
 *
 *   frame_rows    ik_qp.frame_rows (frame_residual, _quaternion, _mul3, the cost products);
 *   qp_finish     the element-wise end of ik_qp.DirectQP.assemble (H's diagonal, c's
 *                 posture terms, the bounds), which numpy spends a call per operation on;
 *   delta_target  one arm's step of control_modes.TaskSpaceTargets.apply_deltas (the
 *                 position and _axis_angle_rows; the rotation product stays numpy's);
 *   in_frame      one arm's target in TaskSpaceTargets.in_frame;
 *   task_space_assemble (with qp_plan, target_plan, qp_assemble, set_native): all of the
 *                 above and the products between them in one call per control step (the
 *                 fused step, below).
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
static void rows_core(const double *pos, const double *m, const double *target_pos,
                      const double *target_mat, const double *cost, double *error,
                      double *block) {
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
}

static int rows(PyObject *const *args, double *error, double *block) {
  double pos[3], m[9], target_pos[3], target_mat[9], cost[6];
  if (!read_floats(args[0], pos, 3, "pos") || !read_floats(args[1], m, 9, "mat") ||
      !read_floats(args[2], target_pos, 3, "target_pos") ||
      !read_floats(args[3], target_mat, 9, "target_mat") || !read_floats(args[4], cost, 6, "cost"))
    return 0;
  rows_core(pos, m, target_pos, target_mat, cost, error, block);
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

/* The element-wise end of DirectQP.assemble, on n coordinates: h (n x n) and c in place,
 * upper and lower written. */
static void finish_core(Py_ssize_t n, double *h, double *c, const double *q,
                        const double *diagonal, const double *posture_weight,
                        const double *offset, double limit_gain, const double *gain_upper,
                        const double *gain_lower, const double *cap, const double *floor,
                        double *upper, double *lower) {
  for (Py_ssize_t i = 0; i < n * n; i++) h[i] = h[i] + diagonal[i];   /* h += diagonal */
  for (Py_ssize_t i = 0; i < n; i++) {
    c[i] = c[i] + posture_weight[i] * q[i];   /* c += posture_weight * q */
    c[i] = c[i] - offset[i];               /* c -= posture_offset */
    double gain_q = limit_gain * q[i];
    upper[i] = np_min(gain_upper[i] - gain_q, cap[i]);
    lower[i] = np_max(gain_lower[i] - gain_q, floor[i]);
  }
}

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
    finish_core(n, h, c, q, diagonal, posture_weight, offset, limit_gain, gain_upper,
                gain_lower, cap, floor, upper, lower);
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

/* One arm's step of TaskSpaceTargets.apply_deltas: the new target position into pos_out;
 * where the move turns, the turn's rotation matrix (_axis_angle_rows) into turn_out and 1
 * returned, else 0. */
static int delta_core(const double *p, const double *move, const double *tcp, double step,
                      double turn, double max_lag, const double *low, const double *high,
                      double *pos_out, double *turn_out) {
  double target[3] = {p[0] + move[0] * step, p[1] + move[1] * step, p[2] + move[2] * step};
  double lag[3] = {target[0] - tcp[0], target[1] - tcp[1], target[2] - tcp[2]};
  double distance = sqrt(lag[0] * lag[0] + lag[1] * lag[1] + lag[2] * lag[2]);
  if (distance > max_lag) {
    for (int k = 0; k < 3; k++) target[k] = tcp[k] + lag[k] * (max_lag / distance);
  }
  for (int k = 0; k < 3; k++) pos_out[k] = py_clamp(target[k], low[k], high[k]);
  double x = move[3] * turn, y = move[4] * turn, z = move[5] * turn;
  if (!(x != 0.0 || y != 0.0 || z != 0.0)) return 0;   /* Python's `x or y or z`: NaN turns */
  double *r = turn_out;
  double angle = sqrt(x * x + y * y + z * z);
  if (angle <= 1e-12) {
    static const double identity[9] = {1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0};
    memcpy(r, identity, sizeof(identity));
    return 1;
  }
  double s = sin(angle * 0.5) / angle;
  double w = cos(angle * 0.5);
  x = x * s; y = y * s; z = z * s;
  double ww = w * w, xx = x * x, yy = y * y, zz = z * z;
  double wx = w * x, wy = w * y, wz = w * z, xy = x * y, xz = x * z, yz = y * z;
  r[0] = ww + xx - yy - zz; r[1] = 2 * (xy - wz);      r[2] = 2 * (xz + wy);
  r[3] = 2 * (xy + wz);     r[4] = ww - xx + yy - zz;  r[5] = 2 * (yz - wx);
  r[6] = 2 * (xz - wy);     r[7] = 2 * (yz + wx);      r[8] = ww - xx - yy + zz;
  return 1;
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
  Py_buffer out;
  if (!get_doubles(args[8], &out, 9, 1, "turn_out")) return NULL;
  double pos[3], turning[9];
  int turned = delta_core(p, move, tcp, step, turn, max_lag, low, high, pos, turning);
  if (turned) memcpy(out.buf, turning, sizeof(turning));
  PyBuffer_Release(&out);
  PyObject *pos_list = float_list(pos, 3);
  if (pos_list == NULL) return NULL;
  return Py_BuildValue("(NO)", pos_list, turned ? Py_True : Py_False);
}

/* One arm of TaskSpaceTargets.in_frame: position p (3) and rotation m (9) in the world, into
 * the frame at o turned by r (row-major), written into pos (3) and rot (9). */
static void in_frame_core(const double *p, const double *m, const double *o, const double *r,
                          double *pos, double *rot) {
  double x = p[0] - o[0], y = p[1] - o[1], z = p[2] - o[2];
  pos[0] = r[0] * x + r[3] * y + r[6] * z;
  pos[1] = r[1] * x + r[4] * y + r[7] * z;
  pos[2] = r[2] * x + r[5] * y + r[8] * z;
  /* rot = r^T m */
  rot[0] = r[0] * m[0] + r[3] * m[3] + r[6] * m[6];
  rot[1] = r[0] * m[1] + r[3] * m[4] + r[6] * m[7];
  rot[2] = r[0] * m[2] + r[3] * m[5] + r[6] * m[8];
  rot[3] = r[1] * m[0] + r[4] * m[3] + r[7] * m[6];
  rot[4] = r[1] * m[1] + r[4] * m[4] + r[7] * m[7];
  rot[5] = r[1] * m[2] + r[4] * m[5] + r[7] * m[8];
  rot[6] = r[2] * m[0] + r[5] * m[3] + r[8] * m[6];
  rot[7] = r[2] * m[1] + r[5] * m[4] + r[8] * m[7];
  rot[8] = r[2] * m[2] + r[5] * m[5] + r[8] * m[8];
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
  double pos[3], rot[9];
  in_frame_core(p, m, o, r, pos, rot);
  PyObject *pos_list = float_list(pos, 3);
  if (pos_list == NULL) return NULL;
  PyObject *rot_list = float_list(rot, 9);
  if (rot_list == NULL) {
    Py_DECREF(pos_list);
    return NULL;
  }
  return Py_BuildValue("(NN)", pos_list, rot_list);
}


/* ---- The fused task-space step -------------------------------------------------------
 *
 * task_space_assemble runs TaskSpaceTargets.apply_deltas and in_frame, DifferentialIK.step's
 * clip and DirectQP.assemble in one call, leaving DAQP's solve to Python. It calls the very
 * functions the Python does, reached by address (set_native, from compiled_kernels): MuJoCo's
 * mj_kinematics, mj_comPos and mj_jacSite, and the cblas_dgemm, cblas_dsyrk and cblas_dgemv of
 * the BLAS numpy was built with, with the arguments numpy's matmul passes them for these
 * shapes (numpy/_core/src/umath/matmul.c.src), so its numbers are the Python's to the bit.
 */

typedef long long blas_int;   /* numpy's bundled OpenBLAS is ILP64 */
typedef void (*mj_stage_fn)(const void *model, void *data);
typedef void (*mj_jac_site_fn)(const void *model, const void *data, double *jacp, double *jacr,
                               int site);
typedef void (*dgemm_fn)(int order, int trans_a, int trans_b, blas_int m, blas_int n,
                         blas_int k, double alpha, const double *a, blas_int lda,
                         const double *b, blas_int ldb, double beta, double *c, blas_int ldc);
typedef void (*dsyrk_fn)(int order, int uplo, int trans, blas_int n, blas_int k, double alpha,
                         const double *a, blas_int lda, double beta, double *c, blas_int ldc);
typedef void (*dgemv_fn)(int order, int trans, blas_int m, blas_int n, double alpha,
                         const double *a, blas_int lda, const double *x, blas_int incx,
                         double beta, double *y, blas_int incy);
enum { CBLAS_ROW_MAJOR = 101, CBLAS_NO_TRANS = 111, CBLAS_TRANS = 112, CBLAS_UPPER = 121 };

static struct {
  mj_stage_fn kinematics, com_pos;
  mj_jac_site_fn jac_site;
  dgemm_fn gemm;
  dsyrk_fn syrk;
  dgemv_fn gemv;
} native;

#define MAX_SITES 8
#define MAX_NV 256   /* qp_assemble reads q onto the stack */

/* DirectQP's constants and buffers (qp_plan). */
typedef struct {
  PyObject *keep;   /* the arrays behind the pointers, alive while the plan is (first: Plan) */
  const void *model;
  void *data;
  Py_ssize_t nv, sites;
  int site_ids[MAX_SITES];
  double *qpos, *site_xpos, *site_xmat;   /* the IK model's MjData */
  double *jac, *blocks, *w, *weighted, *cost, *weight;
  double *h, *c, *upper, *lower, *q, *low, *high;
  double *diagonal, *posture_weight, *posture_offset, *gain_upper, *gain_lower, *cap, *floor;
  double limit_gain;
} QPPlan;

/* TaskSpaceTargets' state and constants (target_plan). */
typedef struct {
  PyObject *keep;   /* as QPPlan's */
  Py_ssize_t arms;
  double *pos, *rot, *turns, *low, *high;
  double step, turn, max_lag, origin[3], rotation[9];
} TargetPlan;

static const char QP_PLAN[] = "ikea_suite.qp_plan";
static const char TARGET_PLAN[] = "ikea_suite.target_plan";

/* What both plans begin with. */
typedef struct {
  PyObject *keep;
} Plan;

static void discard_plan(void *plan) {
  if (plan == NULL) return;
  Py_XDECREF(((Plan *)plan)->keep);
  PyMem_Free(plan);
}

static void free_plan(PyObject *capsule) {
  discard_plan(PyCapsule_GetPointer(capsule, PyCapsule_GetName(capsule)));
}

/* A capsule owning `plan` (freed here if the capsule cannot be made). */
static PyObject *plan_capsule(void *plan, const char *name) {
  PyObject *capsule = PyCapsule_New(plan, name, free_plan);
  if (capsule == NULL) discard_plan(plan);
  return capsule;
}

/* Pointers to the data of `count` arrays, args[0..count), each of counts[i] contiguous
 * float64 (at least counts[i] where at_least[i]), all writable; the arrays are packed into
 * *keep. 0 with an exception on error. */
static int array_pointers(PyObject *const *args, int count, const Py_ssize_t *counts,
                          const int *at_least, const char *const *names, double **out,
                          PyObject **keep) {
  *keep = PyTuple_New(count);
  if (*keep == NULL) return 0;
  for (int i = 0; i < count; i++) {
    Py_buffer view;
    if (PyObject_GetBuffer(args[i], &view, PyBUF_C_CONTIGUOUS | PyBUF_FORMAT | PyBUF_WRITABLE))
      goto fail;
    Py_ssize_t length = view.len / (Py_ssize_t)sizeof(double);
    Py_ssize_t want = counts[i];
    PyBuffer_Release(&view);
    if (at_least[i] && length >= want) want = length;
    if (!get_doubles(args[i], &view, want, 1, names[i])) goto fail;
    out[i] = (double *)view.buf;   /* numpy keeps it there while the array is referenced */
    PyBuffer_Release(&view);
    Py_INCREF(args[i]);
    PyTuple_SET_ITEM(*keep, i, args[i]);
  }
  return 1;
fail:
  Py_CLEAR(*keep);
  return 0;
}

static PyObject *set_native(PyObject *self, PyObject *const *args, Py_ssize_t nargs) {
  (void)self;
  if (wrong_nargs(nargs, 6, "set_native(mj_kinematics, mj_comPos, mj_jacSite, cblas_dgemm, "
                            "cblas_dsyrk, cblas_dgemv)"))
    return NULL;
  void *address[6];
  for (int i = 0; i < 6; i++) {
    address[i] = PyLong_AsVoidPtr(args[i]);
    if (address[i] == NULL) {
      if (!PyErr_Occurred()) PyErr_SetString(PyExc_ValueError, "a function address is 0");
      return NULL;
    }
  }
  native.kinematics = (mj_stage_fn)address[0];
  native.com_pos = (mj_stage_fn)address[1];
  native.jac_site = (mj_jac_site_fn)address[2];
  native.gemm = (dgemm_fn)address[3];
  native.syrk = (dsyrk_fn)address[4];
  native.gemv = (dgemv_fn)address[5];
  Py_RETURN_NONE;
}

#define QP_ARRAYS 23
static PyObject *qp_plan(PyObject *self, PyObject *const *args, Py_ssize_t nargs) {
  (void)self;
  if (wrong_nargs(nargs, 5 + QP_ARRAYS,
                  "qp_plan(model_address, data_address, site_ids, nv, limit_gain, qpos, "
                  "site_xpos, site_xmat, jac, blocks, w, weighted, cost, weight, h, c, upper, "
                  "lower, q, low, high, diagonal, posture_weight, posture_offset, gain_upper, "
                  "gain_lower, cap, floor)"))
    return NULL;
  QPPlan *plan = PyMem_Calloc(1, sizeof(QPPlan));
  if (plan == NULL) return PyErr_NoMemory();
  plan->model = PyLong_AsVoidPtr(args[0]);
  plan->data = PyLong_AsVoidPtr(args[1]);
  plan->nv = PyLong_AsSsize_t(args[3]);
  plan->limit_gain = PyFloat_AsDouble(args[4]);
  if (PyErr_Occurred()) goto fail;
  if (plan->model == NULL || plan->data == NULL) {
    PyErr_SetString(PyExc_ValueError, "model_address and data_address must not be 0");
    goto fail;
  }
  if (plan->nv < 1 || plan->nv > MAX_NV) {
    PyErr_Format(PyExc_ValueError, "nv must be 1 to %d", MAX_NV);
    goto fail;
  }
  PyObject *sites = PySequence_Fast(args[2], "site_ids");
  if (sites == NULL) goto fail;
  plan->sites = PySequence_Fast_GET_SIZE(sites);
  if (plan->sites < 1 || plan->sites > MAX_SITES) {
    PyErr_Format(PyExc_ValueError, "site_ids must hold 1 to %d sites", MAX_SITES);
    Py_DECREF(sites);
    goto fail;
  }
  Py_ssize_t nsite_max = 0;
  for (Py_ssize_t i = 0; i < plan->sites; i++) {
    long id = PyLong_AsLong(PySequence_Fast_GET_ITEM(sites, i));
    if (id < 0) {
      if (!PyErr_Occurred()) PyErr_SetString(PyExc_ValueError, "negative site id");
      Py_DECREF(sites);
      goto fail;
    }
    plan->site_ids[i] = (int)id;
    if (id + 1 > nsite_max) nsite_max = id + 1;
  }
  Py_DECREF(sites);
  Py_ssize_t n = plan->nv, s = plan->sites;
  /* The MjData's site rows need only reach the largest site id. */
  const Py_ssize_t counts[QP_ARRAYS] = {
      n, 3 * nsite_max, 9 * nsite_max, s * 6 * n, s * 36, s * 6 * n, 6 * s, 6 * s, 6 * s,
      n * n, n, n, n, n, n, n, n * n, n, n, n, n, n, n};
  static const int at_least[QP_ARRAYS] = {0, 1, 1};
  static const char *const names[QP_ARRAYS] = {
      "qpos", "site_xpos", "site_xmat", "jac", "blocks", "w", "weighted", "cost", "weight",
      "h", "c", "upper", "lower", "q", "low", "high", "diagonal", "posture_weight",
      "posture_offset", "gain_upper", "gain_lower", "cap", "floor"};
  double *p[QP_ARRAYS];
  if (!array_pointers(args + 5, QP_ARRAYS, counts, at_least, names, p, &plan->keep)) goto fail;
  plan->qpos = p[0]; plan->site_xpos = p[1]; plan->site_xmat = p[2]; plan->jac = p[3];
  plan->blocks = p[4]; plan->w = p[5]; plan->weighted = p[6]; plan->cost = p[7];
  plan->weight = p[8]; plan->h = p[9]; plan->c = p[10]; plan->upper = p[11];
  plan->lower = p[12]; plan->q = p[13]; plan->low = p[14]; plan->high = p[15];
  plan->diagonal = p[16]; plan->posture_weight = p[17]; plan->posture_offset = p[18];
  plan->gain_upper = p[19]; plan->gain_lower = p[20]; plan->cap = p[21]; plan->floor = p[22];
  return plan_capsule(plan, QP_PLAN);
fail:
  discard_plan(plan);
  return NULL;
}

#define TARGET_ARRAYS 5
static PyObject *target_plan(PyObject *self, PyObject *const *args, Py_ssize_t nargs) {
  (void)self;
  if (wrong_nargs(nargs, 6 + TARGET_ARRAYS,
                  "target_plan(arms, step, turn, max_lag, origin, rotation, pos, rot, turns, "
                  "low, high)"))
    return NULL;
  TargetPlan *plan = PyMem_Calloc(1, sizeof(TargetPlan));
  if (plan == NULL) return PyErr_NoMemory();
  plan->arms = PyLong_AsSsize_t(args[0]);
  plan->step = PyFloat_AsDouble(args[1]);
  plan->turn = PyFloat_AsDouble(args[2]);
  plan->max_lag = PyFloat_AsDouble(args[3]);
  if (PyErr_Occurred()) goto fail;
  if (plan->arms < 1 || plan->arms > MAX_SITES) {
    PyErr_Format(PyExc_ValueError, "arms must be 1 to %d", MAX_SITES);
    goto fail;
  }
  if (!read_floats(args[4], plan->origin, 3, "origin") ||
      !read_floats(args[5], plan->rotation, 9, "rotation"))
    goto fail;
  Py_ssize_t a = plan->arms;
  const Py_ssize_t counts[TARGET_ARRAYS] = {3 * a, 9 * a, 9 * a, 3 * a, 3 * a};
  static const int at_least[TARGET_ARRAYS] = {0};
  static const char *const names[TARGET_ARRAYS] = {"pos", "rot", "turns", "low", "high"};
  double *p[TARGET_ARRAYS];
  if (!array_pointers(args + 6, TARGET_ARRAYS, counts, at_least, names, p, &plan->keep))
    goto fail;
  plan->pos = p[0]; plan->rot = p[1]; plan->turns = p[2]; plan->low = p[3]; plan->high = p[4];
  return plan_capsule(plan, TARGET_PLAN);
fail:
  discard_plan(plan);
  return NULL;
}

/* DifferentialIK.step's clip of q into plan->q, then DirectQP.assemble at it towards
 * `targets` (per site: position 3, rotation 9 row-major, in the IK model's frame). */
static void assemble_core(QPPlan *plan, const double *q, const double *targets) {
  Py_ssize_t n = plan->nv, s = plan->sites;
  for (Py_ssize_t i = 0; i < n; i++) {   /* np.minimum(np.maximum(q, low), high) */
    plan->q[i] = np_min(np_max(q[i], plan->low[i]), plan->high[i]);
  }
  memcpy(plan->qpos, plan->q, n * sizeof(double));
  native.kinematics(plan->model, plan->data);
  native.com_pos(plan->model, plan->data);
  for (Py_ssize_t i = 0; i < s; i++) {
    double *jac = plan->jac + i * 6 * n;
    native.jac_site(plan->model, plan->data, jac, jac + 3 * n, plan->site_ids[i]);
  }
  for (Py_ssize_t i = 0; i < s; i++) {   /* DirectQP._rows_compiled */
    int site = plan->site_ids[i];
    double error[6];
    const double *target = targets + 12 * i;
    rows_core(plan->site_xpos + 3 * site, plan->site_xmat + 9 * site, target, target + 3,
              plan->cost + 6 * i, error, plan->blocks + 36 * i);
    for (int k = 0; k < 6; k++) plan->weighted[6 * i + k] = plan->weight[6 * i + k] * error[k];
  }
  for (Py_ssize_t i = 0; i < s; i++) {   /* np.matmul(blocks, jac, out=w), site by site */
    native.gemm(CBLAS_ROW_MAJOR, CBLAS_NO_TRANS, CBLAS_NO_TRANS, 6, n, 6, 1.0,
                plan->blocks + 36 * i, 6, plan->jac + i * 6 * n, n, 0.0, plan->w + i * 6 * n, n);
  }
  /* h = w.T @ w: numpy's syrk of the upper triangle, then its copy to the lower. */
  native.syrk(CBLAS_ROW_MAJOR, CBLAS_UPPER, CBLAS_TRANS, n, 6 * s, 1.0, plan->w, n, 0.0,
              plan->h, n);
  for (Py_ssize_t i = 0; i < n; i++) {
    for (Py_ssize_t j = i + 1; j < n; j++) plan->h[j * n + i] = plan->h[i * n + j];
  }
  /* c = weighted @ w: numpy's gemv of w transposed. */
  native.gemv(CBLAS_ROW_MAJOR, CBLAS_TRANS, 6 * s, n, 1.0, plan->w, n, plan->weighted, 1, 0.0,
              plan->c, 1);
  finish_core(n, plan->h, plan->c, plan->q, plan->diagonal, plan->posture_weight,
              plan->posture_offset, plan->limit_gain, plan->gain_upper, plan->gain_lower,
              plan->cap, plan->floor, plan->upper, plan->lower);
}

static QPPlan *get_qp_plan(PyObject *capsule) {
  if (native.gemm == NULL) {
    PyErr_SetString(PyExc_RuntimeError, "set_native has not been called");
    return NULL;
  }
  return PyCapsule_GetPointer(capsule, QP_PLAN);
}

/* qp_assemble(qp_plan, q, targets): assemble_core; the results are in the plan's h, c,
 * lower, upper and (the clipped q) q arrays. */
static PyObject *qp_assemble(PyObject *self, PyObject *const *args, Py_ssize_t nargs) {
  (void)self;
  if (wrong_nargs(nargs, 3, "qp_assemble(qp_plan, q, targets)")) return NULL;
  QPPlan *plan = get_qp_plan(args[0]);
  if (plan == NULL) return NULL;
  double q[MAX_NV], targets[12 * MAX_SITES];
  if (!read_floats(args[1], q, plan->nv, "q") ||
      !read_floats(args[2], targets, 12 * plan->sites, "targets"))
    return NULL;
  assemble_core(plan, q, targets);
  Py_RETURN_NONE;
}

/* The targets behind `aim` moved by one delta action per arm (rows of `width`, the first 6
 * read): TaskSpaceTargets.apply_deltas with the tools at tcp. */
static void move_targets(TargetPlan *aim, const double *actions, Py_ssize_t width,
                         const double *tcp) {
  for (Py_ssize_t i = 0; i < aim->arms; i++) {
    double *pos = aim->pos + 3 * i, *rot = aim->rot + 9 * i, *turning = aim->turns + 9 * i;
    double moved[3];
    int turned = delta_core(pos, actions + width * i, tcp + 3 * i, aim->step, aim->turn,
                            aim->max_lag, aim->low + 3 * i, aim->high + 3 * i, moved, turning);
    memcpy(pos, moved, sizeof(moved));
    if (turned) {   /* rot = turning @ rot: numpy's gemm, into a new array, copied back */
      double product[9];
      native.gemm(CBLAS_ROW_MAJOR, CBLAS_NO_TRANS, CBLAS_NO_TRANS, 3, 3, 3, 1.0, turning, 3,
                  rot, 3, 0.0, product, 3);
      memcpy(rot, product, sizeof(product));
    }
  }
}

/* task_space_assemble(qp_plan, target_plan, actions, tcp_pos, q): TaskSpaceTargets
 * .apply_deltas(actions, tcp_pos) (actions: arms rows of at least 6; None leaves the targets
 * as they are, and tcp_pos is not read), the targets in_frame of the plan's origin and
 * rotation, and qp_assemble at q towards them. */
static PyObject *task_space_assemble(PyObject *self, PyObject *const *args, Py_ssize_t nargs) {
  (void)self;
  if (wrong_nargs(nargs, 5, "task_space_assemble(qp_plan, target_plan, actions, tcp_pos, q)"))
    return NULL;
  QPPlan *plan = get_qp_plan(args[0]);
  if (plan == NULL) return NULL;
  TargetPlan *aim = PyCapsule_GetPointer(args[1], TARGET_PLAN);
  if (aim == NULL) return NULL;
  if (aim->arms != plan->sites) {
    PyErr_SetString(PyExc_ValueError, "the plans have different numbers of arms");
    return NULL;
  }
  Py_ssize_t arms = aim->arms;
  Py_buffer q;
  if (!get_doubles(args[4], &q, plan->nv, 0, "q")) return NULL;
  if (args[2] != Py_None) {
    Py_buffer actions, tcp;
    Py_ssize_t width = 0;
    if (PyObject_GetBuffer(args[2], &actions, PyBUF_C_CONTIGUOUS | PyBUF_FORMAT) == 0) {
      width = actions.len / (Py_ssize_t)sizeof(double) / arms;
      PyBuffer_Release(&actions);
      if (width < 6) {
        PyErr_SetString(PyExc_ValueError, "actions must hold at least 6 numbers per arm");
      } else if (get_doubles(args[2], &actions, width * arms, 0, "actions")) {
        if (get_doubles(args[3], &tcp, 3 * arms, 0, "tcp_pos")) {
          move_targets(aim, actions.buf, width, tcp.buf);
          PyBuffer_Release(&tcp);
        }
        PyBuffer_Release(&actions);
      }
    }
    if (PyErr_Occurred()) {
      PyBuffer_Release(&q);
      return NULL;
    }
  }
  double targets[12 * MAX_SITES];
  for (Py_ssize_t i = 0; i < arms; i++) {
    in_frame_core(aim->pos + 3 * i, aim->rot + 9 * i, aim->origin, aim->rotation,
                  targets + 12 * i, targets + 12 * i + 3);
  }
  assemble_core(plan, (const double *)q.buf, targets);
  PyBuffer_Release(&q);
  Py_RETURN_NONE;
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
    {"set_native", (PyCFunction)(void (*)(void))set_native, METH_FASTCALL,
     "set_native(mj_kinematics, mj_comPos, mj_jacSite, cblas_dgemm, cblas_dsyrk, "
     "cblas_dgemv): the functions' addresses, for the fused step."},
    {"qp_plan", (PyCFunction)(void (*)(void))qp_plan, METH_FASTCALL,
     "qp_plan(...) -> capsule: ik_qp.DirectQP's constants and buffers for qp_assemble."},
    {"target_plan", (PyCFunction)(void (*)(void))target_plan, METH_FASTCALL,
     "target_plan(...) -> capsule: TaskSpaceTargets' state for task_space_assemble."},
    {"qp_assemble", (PyCFunction)(void (*)(void))qp_assemble, METH_FASTCALL,
     "qp_assemble(qp_plan, q, targets): DifferentialIK.step's clip and DirectQP.assemble."},
    {"task_space_assemble", (PyCFunction)(void (*)(void))task_space_assemble, METH_FASTCALL,
     "task_space_assemble(qp_plan, target_plan, actions, tcp_pos, q): the target update, "
     "in_frame and qp_assemble in one call."},
    {NULL, NULL, 0, NULL}};

static struct PyModuleDef module = {PyModuleDef_HEAD_INIT, "_ik_kernels",
                                    "Compiled twins of pieces of ik_qp.", -1, methods,
                                    NULL, NULL, NULL, NULL};

PyMODINIT_FUNC PyInit__ik_kernels(void) { return PyModule_Create(&module); }
