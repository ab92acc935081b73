"""MJX-Warp's fixed contact and constraint buffers: their size per model, and their overflow.

MJX's Warp implementation allocates its buffers once, in `mjx.make_data`:
contacts for all worlds together in one buffer of `naconmax` entries (MJX
takes the total; mujoco_warp's per-world `nconmax` is `naconmax // worlds`),
and `njmax` constraint rows per world. A step that needs more keeps going
without the excess: Warp drops the broadphase candidates or contacts beyond
`naconmax` and the rows beyond `njmax`, prints "broadphase overflow - please
increase nconmax beyond X or naconmax beyond Y" (or narrowphase, nefc), and
sets a bit in the world's `overflow` word. The physics of every world is then
wrong (the contact buffer is shared, so one crowded world starves the rest).
MJX's JAX implementation has no fixed buffers: it computes every possible
contact of the model at every step.

Sizing rule, per model (`sizing`): drop every part on each of its six faces
(part axes down) onto the floor and let it settle for SETTLE_S, with CPU
MuJoCo on the batched model itself; per part keep the most contacts,
broadphase candidates (Warp's plane and bounding-sphere filters) and contact
constraint rows seen at any step over the six drops; add the parts up, as if
every part lay on its worst face at once. Then per world

    nconmax = ceil(MARGIN * max(contacts, candidates))
    njmax   = ceil(MARGIN * (contact rows + other rows)) + equality rows

where equality rows are the static bound of every weld that can be on at once
(6 rows each), and `naconmax = nconmax * worlds`. Scattered starts settled
the same way (`settle`) stay below the face bound (tests/test_batch_contact_buffers.py).

After every env step `overflow` reads the world's overflow word (buffer bits
only) and the peak demand over the step's substeps, and `OverflowWatch`
warns on the host naming the buffer and the size that would have fitted.
"""

import dataclasses
import functools
import math
import typing
import warnings

import jax.numpy as jnp
import mujoco
import numpy as np

from ikea_suite import errors

MARGIN = 1.5          # on measured counts: Warp's narrowphase may emit contacts CPU MuJoCo merges
SETTLE_S = 0.2        # s each face drop runs: it lands within 0.05 s; a toppling part ends on
                      # another face, which has its own drop
DROP = 5e-3           # m above the floor a face drop starts (its lowest box corner)
FACES = tuple((axis, sign) for axis in range(3) for sign in (1, -1))
WELD_ROWS = 6         # constraint rows of one active weld equality

# mujoco_warp's OverflowType bits (types.py) for the buffers sized at make_data, and the
# make_data argument that sizes each. The other bits (solver iterations, height fields,
# sensors) are not buffers and are ignored here.
OVERFLOW_BUFFERS = {
    1 << 0: "njmax",          # NEFC: a world needed more constraint rows
    1 << 1: "njmax_nnz",      # NJMAX_NNZ: non-zeros of the sparse constraint Jacobian
    1 << 2: "naconmax",       # BROADPHASE: candidate pairs of all worlds
    1 << 3: "naconmax",       # NARROWPHASE: contacts of all worlds
    1 << 4: "naccdmax",       # CCD: convex (GJK/EPA) contacts of all worlds
    1 << 7: "nvmax",          # NVMAX: awake dofs (islands)
}
BUFFER_BITS = functools.reduce(lambda a, b: a | b, OVERFLOW_BUFFERS)
_CONTACT_ROWS = (mujoco.mjtConstraint.mjCNSTR_CONTACT_FRICTIONLESS,
                 mujoco.mjtConstraint.mjCNSTR_CONTACT_PYRAMIDAL,
                 mujoco.mjtConstraint.mjCNSTR_CONTACT_ELLIPTIC)
_EQUALITY_ROWS = (mujoco.mjtConstraint.mjCNSTR_EQUALITY,)


class Counts(typing.NamedTuple):
  """Buffer demand of one world.

  Attributes:
    contacts: contacts (MuJoCo's ncon).
    candidates: geom pairs through Warp's broadphase (plane and bounding-sphere filters).
    contact_rows: constraint rows of the contacts.
    other_rows: constraint rows that are neither contacts nor equalities (limits, friction).
  """
  contacts: int
  candidates: int
  contact_rows: int
  other_rows: int

  def peak(self, other):
    """Field-wise maximum."""
    return Counts(*(max(a, b) for a, b in zip(self, other)))


@dataclasses.dataclass(frozen=True)
class Sizing:
  """Warp buffer sizes of one model.

  Attributes:
    measured: the worst Counts the rule measured (None for sizes given by hand).
    equality_rows: rows of every equality that can be on at once (static bound).
    margin: factor on the measured counts.
    nconmax: contacts per world (Warp's broadphase candidates use the same buffer).
    njmax: constraint rows per world.
  """
  measured: Counts
  equality_rows: int
  margin: float
  nconmax: int
  njmax: int

  def naconmax(self, num_worlds):
    """Contacts of `num_worlds` worlds: the shared buffer's size."""
    return self.nconmax * max(1, int(num_worlds or 1))


def size(measured, equality_rows, margin=MARGIN):
  """The Sizing of `measured` worst counts (see the module docstring).

  Args:
    measured: Counts, worst case of one world.
    equality_rows: rows of every equality that can be on at once.
    margin: factor (>= 1) on the measured counts.

  Returns:
    A Sizing.
  """
  nconmax = max(1, math.ceil(margin * max(measured.contacts, measured.candidates)))
  njmax = (math.ceil(margin * (measured.contact_rows + measured.other_rows))
           + int(equality_rows))
  return Sizing(measured=measured, equality_rows=int(equality_rows), margin=margin,
                nconmax=nconmax, njmax=max(1, njmax))


def given(buffer_sizes):
  """A Sizing of (nconmax, njmax) per world chosen by hand; raises OptionValueError unless
  both are integers >= 1."""
  sizes = tuple(buffer_sizes) if isinstance(buffer_sizes, (tuple, list)) else ()
  if len(sizes) != 2 or any(isinstance(v, bool) or not isinstance(v, (int, np.integer))
                            or v < 1 for v in sizes):
    raise errors.OptionValueError(
        f"buffer_sizes must be (nconmax, njmax), two integers >= 1, got {buffer_sizes!r}")
  return Sizing(measured=None, equality_rows=0, margin=MARGIN, nconmax=int(sizes[0]),
                njmax=int(sizes[1]))


def collidable_pairs(model):
  """(geom1, geom2) index arrays of the pairs Warp's broadphase considers (mujoco_warp's
  nxn pair filter: contype/conaffinity, same or parent body, dof-less bodies, excludes,
  explicit pairs)."""
  g1, g2 = np.triu_indices(model.ngeom, k=1)
  b1, b2 = model.geom_bodyid[g1], model.geom_bodyid[g2]
  w1, w2 = model.body_weldid[b1], model.body_weldid[b2]
  wp1 = model.body_weldid[model.body_parentid[w1]]
  wp2 = model.body_weldid[model.body_parentid[w2]]
  filterparent = not model.opt.disableflags & mujoco.mjtDisableBit.mjDSBL_FILTERPARENT
  parent = filterparent & (w1 != 0) & (w2 != 0) & ((w1 == wp2) | (w2 == wp1))
  no_dofs = (model.body_dofnum[w1] == 0) & (model.body_dofnum[w2] == 0)
  mask = ((model.geom_contype[g1] & model.geom_conaffinity[g2])
          | (model.geom_contype[g2] & model.geom_conaffinity[g1])).astype(bool)
  exclude = np.isin((b1 << 16) + b2, model.exclude_signature)
  keep = mask & (w1 != w2) & ~no_dofs & ~parent & ~exclude
  for i in range(model.npair):
    a, b = sorted((model.pair_geom1[i], model.pair_geom2[i]))
    keep |= (g1 == a) & (g2 == b)
  return g1[keep], g2[keep]


def _candidates(model, data, pairs):
  """(pairs,) bool: the pair passes Warp's plane or bounding-sphere broadphase filter."""
  g1, g2 = pairs
  margin = (model.geom_margin[g1] + model.geom_gap[g1] + model.geom_margin[g2]
            + model.geom_gap[g2])
  r1, r2 = model.geom_rbound[g1], model.geom_rbound[g2]
  p1, p2 = data.geom_xpos[g1], data.geom_xpos[g2]
  n1 = data.geom_xmat[g1].reshape(-1, 3, 3)[:, :, 2]   # plane normals: the geom's z axis
  n2 = data.geom_xmat[g2].reshape(-1, 3, 3)[:, :, 2]
  plane1 = np.einsum("ij,ij->i", p2 - p1, n1) <= r2 + margin
  plane2 = np.einsum("ij,ij->i", p1 - p2, n2) <= r1 + margin
  sphere = np.linalg.norm(p2 - p1, axis=1) <= r1 + r2 + margin
  return np.where(r1 == 0, plane1, np.where(r2 == 0, plane2, sphere))


def counts_by_owner(model, data, pairs, owner, num_owners):
  """Counts of `data` (after mj_forward or mj_step) split by owner.

  Args:
    model, data: mujoco.MjModel and MjData.
    pairs: collidable_pairs(model).
    owner: (ngeom,) int, the owner of each geom (a part index) or -1; a contact or
      candidate pair belongs to the owner of its first owned geom.
    num_owners: number of owners.

  Returns:
    (per-owner (num_owners, 3) int array of contacts, candidates, contact rows; other rows
    of the whole world).
  """
  out = np.zeros((num_owners, 3), dtype=int)
  def attribute(g1, g2):
    o = np.where(owner[g1] >= 0, owner[g1], owner[g2])
    return o[o >= 0]
  geom = data.contact.geom[:data.ncon]
  np.add.at(out[:, 0], attribute(geom[:, 0], geom[:, 1]), 1)
  g1, g2 = pairs
  hit = _candidates(model, data, pairs)
  np.add.at(out[:, 1], attribute(g1[hit], g2[hit]), 1)
  efc_type = data.efc_type[:data.nefc]
  contact_row = np.isin(efc_type, _CONTACT_ROWS)
  row_contact = data.efc_id[:data.nefc][contact_row]
  np.add.at(out[:, 2], attribute(geom[row_contact, 0], geom[row_contact, 1]), 1)
  other = int((~contact_row & ~np.isin(efc_type, _EQUALITY_ROWS)).sum())
  return out, other


def settle(model, starts, seconds=SETTLE_S, eq_active=None):
  """The worst Counts over every physics step of settling each start with CPU MuJoCo.

  Args:
    model: mujoco.MjModel (the batched env's, batch/model.py).
    starts: iterable of qpos vectors; each is released at rest and stepped for `seconds`.
    seconds: s of simulation per start.
    eq_active: (neq,) bool equalities on during every start (default: the model's eq_active0).

  Returns:
    Counts.
  """
  data = mujoco.MjData(model)
  pairs = collidable_pairs(model)
  owner = np.zeros(model.ngeom, dtype=int)
  worst = Counts(0, 0, 0, 0)
  for qpos in starts:
    mujoco.mj_resetData(model, data)
    data.qpos[:] = qpos
    if eq_active is not None:
      data.eq_active[:] = eq_active
    for _ in range(max(1, round(seconds / model.opt.timestep))):
      mujoco.mj_step(model, data)
      per, other = counts_by_owner(model, data, pairs, owner, 1)
      worst = worst.peak(Counts(*(int(x) for x in per[0]), other))
  return worst


def _face_rotation(axis, sign):
  """Rotation that turns part axis `axis` (sign `sign`) to point down."""
  down = np.zeros(3)
  down[axis] = sign
  target = np.array([0.0, 0.0, -1.0])
  cross, dot = np.cross(down, target), float(down @ target)
  if np.linalg.norm(cross) < 1e-12:
    return np.eye(3) if dot > 0 else np.diag([1.0, -1.0, -1.0])
  k = np.array([[0, -cross[2], cross[1]], [cross[2], 0, -cross[0]], [-cross[1], cross[0], 0]])
  return np.eye(3) + k + k @ k / (1 + dot)


def part_faces(batch_model, seconds=SETTLE_S):
  """Per part the worst counts of dropping it on each of its six faces, summed over parts.

  Every part falls at once, on the same face, at its own spot on the floor (spaced by
  their bounding radii so that none touches another), from DROP above its lowest box
  corner; contacts and rows are attributed to the part whose geom they touch.

  Args:
    batch_model: a batch/model.BatchModel.
    seconds: s each drop runs.

  Returns:
    Counts (other_rows: the worst of the whole world).
  """
  bm = batch_model
  model = bm.model
  data = mujoco.MjData(model)
  pairs = collidable_pairs(model)
  part_of_body = {}
  for i, adr in enumerate(bm.part_qpos):
    joint = np.flatnonzero(model.jnt_qposadr == adr)[0]
    part_of_body[int(model.jnt_bodyid[joint])] = i
  owner = np.array([part_of_body.get(int(b), -1) for b in model.geom_bodyid])
  p = bm.num_parts
  corners = np.array([[sx, sy, sz] for sx in (-1, 1) for sy in (-1, 1) for sz in (-1, 1)])
  radius = np.zeros(p)
  local = [[] for _ in range(p)]    # collision box corners of each part, in its frame
  for g in range(len(bm.geom_part)):
    pts = bm.geom_pos[g] + (bm.geom_center[g] + corners * bm.geom_half[g]) @ bm.geom_rot[g].T
    local[bm.geom_part[g]].append(pts)
  local = [np.concatenate(x) if x else np.zeros((1, 3)) for x in local]
  radius = np.array([np.linalg.norm(x, axis=1).max() for x in local])
  x_spot = np.cumsum(2 * radius + 0.1) - radius
  worst = np.zeros((p, 3), dtype=int)
  other_worst = 0
  for axis, sign in FACES:
    rot = _face_rotation(axis, sign)
    quat = np.empty(4)
    mujoco.mju_mat2Quat(quat, rot.ravel())
    mujoco.mj_resetData(model, data)
    data.eq_active[:] = False
    for i in range(p):
      lowest = (local[i] @ rot.T)[:, 2].min()
      adr = bm.part_qpos[i]
      data.qpos[adr:adr + 3] = (x_spot[i], 0.0, DROP - lowest)
      data.qpos[adr + 3:adr + 7] = quat
    for _ in range(max(1, round(seconds / model.opt.timestep))):
      mujoco.mj_step(model, data)
      per, other = counts_by_owner(model, data, pairs, owner, p)
      worst = np.maximum(worst, per)
      other_worst = max(other_worst, other)
  total = worst.sum(axis=0)
  return Counts(int(total[0]), int(total[1]), int(total[2]), other_worst)


def equality_rows(num_grips, num_welds, num_parts):
  """Rows of every weld that can be on at once: the grips, and at most one part weld per
  part pair (loop closures included) of the declared ones."""
  return WELD_ROWS * (num_grips + min(num_welds, num_parts * (num_parts - 1) // 2))


_SIZINGS = {}


def sizing(batch_model, num_grips, margin=MARGIN):
  """The Sizing of a batched model (part_faces, cached per compiled model and margin).

  Args:
    batch_model: a batch/model.BatchModel.
    num_grips: grip welds that can be on at once (the Cursor: 2).
    margin: factor on the measured counts.

  Returns:
    A Sizing.
  """
  key = (id(batch_model.model), num_grips, margin)
  if key not in _SIZINGS:
    measured = part_faces(batch_model)
    _SIZINGS[key] = (batch_model.model, size(
        measured, equality_rows(num_grips, batch_model.welds.num_welds, batch_model.num_parts),
        margin))
  return _SIZINGS[key][1]


# -- on the device ----------------------------------------------------------------------

def cleared(data):
  """`data` with the world's Warp overflow word zeroed (Warp only sets bits), so that after
  the substeps it holds this step's overflows; unchanged on MJX's JAX implementation."""
  impl = getattr(data, "_impl", None)
  if impl is None or not hasattr(impl, "overflow"):
    return data
  return data.replace(_impl=impl.replace(overflow=jnp.zeros_like(impl.overflow)))


def demand(data):
  """(overflow, peak) of one world after a physics step: its Warp overflow word masked to
  the buffer bits (int32), and (contacts or candidates of all worlds in the shared buffer,
  constraint rows of this world) as int32; zeros on MJX's JAX implementation, which has no
  fixed buffers."""
  impl = getattr(data, "_impl", None)
  if impl is None or not hasattr(impl, "overflow"):
    return jnp.int32(0), jnp.zeros(2, dtype=jnp.int32)
  shared = jnp.maximum(jnp.max(impl.nacon), jnp.max(impl.ncollision))
  return ((impl.overflow & BUFFER_BITS).astype(jnp.int32),
          jnp.stack([shared, jnp.max(impl.nefc)]).astype(jnp.int32))


def worse(a, b):
  """Combines two (overflow, peak) of successive substeps: bits or'ed, peaks maxed."""
  return a[0] | b[0], jnp.maximum(a[1], b[1])


# -- on the host ----------------------------------------------------------------------------

def describe(bits):
  """The buffer names of an overflow word, e.g. ["naconmax", "njmax"]."""
  return sorted({name for bit, name in OVERFLOW_BUFFERS.items() if int(bits) & bit})



def overflow_summary(by_model):
  """The line a script prints when buffers overflowed.

  Args:
    by_model: furniture name -> {buffer name: world-steps that overflowed it}.

  Returns:
    str naming each model's buffers and their world-steps.
  """
  return "buffer overflow (contacts or constraint rows dropped): " + "; ".join(
      f"{name} ({', '.join(f'{k}: {v} world-steps' for k, v in totals.items())})"
      for name, totals in by_model.items())

class OverflowWatch:
  """Counts the world-steps whose Warp buffers overflowed and warns, on the host.

  `watch` takes a step's per-world overflow words and peaks (device arrays) and reads the
  previous step's, so the host waits for a step only while the next one is queued;
  `flush` reads the last one.

  Args:
    sizing: the env's Sizing.
    num_worlds: worlds sharing the contact buffer.
  """

  def __init__(self, sizing, num_worlds):
    self.sizing = sizing
    self.num_worlds = max(1, int(num_worlds or 1))
    self.world_steps = {}          # buffer name -> world-steps that overflowed it
    self.peak = np.zeros(2, dtype=int)
    self._pending = None

  def watch(self, overflow, peak):
    """Queues this step's (overflow (worlds,), peak (worlds, 2)) and reads the previous."""
    pending, self._pending = self._pending, (overflow, peak)
    if pending is not None:
      self._read(*pending)

  def flush(self):
    """Reads the queued step; returns the totals (buffer name -> world-steps)."""
    if self._pending is not None:
      pending, self._pending = self._pending, None
      self._read(*pending)
    return dict(self.world_steps)

  @property
  def total(self):
    """World-steps with any buffer overflow so far (after flush)."""
    return sum(self.world_steps.values())

  def _read(self, overflow, peak):
    overflow = np.asarray(overflow).reshape(-1)
    peak = np.asarray(peak).reshape(-1, 2).max(axis=0)
    self.peak = np.maximum(self.peak, peak)
    if not overflow.any():
      return
    names = {}
    for bit, name in OVERFLOW_BUFFERS.items():
      worlds = int(((overflow & bit) != 0).sum())
      if worlds:
        names[name] = max(names.get(name, 0), worlds)
    for name, worlds in names.items():
      self.world_steps[name] = self.world_steps.get(name, 0) + worlds
    warnings.warn(overflow_message(self.sizing, self.num_worlds, names, peak),
                  RuntimeWarning, stacklevel=3)


def overflow_message(sizing, num_worlds, names, peak):
  """The warning text for a step whose buffers `names` (name -> worlds) overflowed."""
  s = sizing
  parts = []
  for name, worlds in sorted(names.items()):
    if name == "naconmax":
      per_world = math.ceil(int(peak[0]) / num_worlds)
      need = math.ceil(s.margin * per_world)
      parts.append(
          f"naconmax = {s.naconmax(num_worlds)} ({s.nconmax} per world x {num_worlds} worlds) "
          f"overflowed: at least {int(peak[0])} contacts or candidates were needed; use "
          f"nconmax >= {need} (naconmax >= {need * num_worlds})")
    elif name == "njmax":
      need = math.ceil(s.margin * int(peak[1]))
      parts.append(f"njmax = {s.njmax} rows per world overflowed in {worlds} worlds: "
                   f"at least {int(peak[1])} rows were needed; use njmax >= {need}")
    else:
      parts.append(f"{name} overflowed in {worlds} worlds")
  return ("MJX-Warp dropped contacts or constraints, so this step's physics is wrong: "
          + "; ".join(parts)
          + ". Pass buffer_sizes=(nconmax, njmax) to ikea_suite.batch.load.")
