"""Assembly sequences found by disassembly: which part goes in next, and along which path.

Starting from the assembled furniture (raised by `lift` above the floor, as
the oracle holds it), parts are taken away one at a time. A part may leave
when the rest stays one connected assembly and the part slides out without
cutting into the rest or the floor: straight along an axis until it is clear
of the rest's bounding box, or a short way along one axis and then sideways
out (a leg drops from under a table top, then moves out). Read backwards this
is an assembly order in which every part goes in along a free path. The root
part (the one the oracle holds) stays to the end.

Only when no part can leave so are two further kinds of path tried, for parts
that fit more closely: along the up axis of one of the part's connectors (the
reverse of a mate's insertion direction, tilted where the mate is: a splayed
leg leaves its seat along the leg), straight or as the first leg of a two-leg
path; and, last, paths on which the part slides along faces it touches (a ring
round a stool's legs, a leg held between a bench's top and its frame), with no
air kept but never cutting in deeper than `PENETRATION` (more than a pair of
parts already overlaps assembled). Furniture that the first kinds of path
take apart never reaches these, so its plan does not depend on them.

Plain MuJoCo on the furniture's document (the spec's, scaled as it is) does the
collision tests; nothing here needs the task or an environment. A plan is kept
with the spec it was made for, so every user of one spec plans it once.
"""

import dataclasses
import logging
import weakref

import mujoco
import numpy as np

from ikea_suite import errors
from ikea_suite import physics_settings
from ikea_suite.assembly import graph
from ikea_suite.props import model_format

PENETRATION = 0.001    # metres of overlap that count as a collision
CLEARANCE = 0.001      # metres of air kept around a part once it is `NEAR` from its place
LOOSE = 0.005          # air around a part that leaves loosely: such parts leave first
NEAR = 0.008           # closer than this a part may slide along a face it will touch
STEP = 0.015           # sampling step along a path (thinner than any two boards together)
MARGIN = 0.03          # extra distance beyond the bounding box
SHORT_MOVE = (0.03, 0.06, 0.10, 0.15)   # first-leg lengths tried for two-leg paths
_AXES = np.concatenate([np.eye(3), -np.eye(3)])
# Between two axes, tried last: a part in a corner touches two perpendicular faces
# (a corner shelf's boards, a cabinet side against its top and back) and slides along
# one of them on every axis, but leaves both at once along their diagonal.
_DIAGONALS = np.array([v / np.sqrt(2) for i in range(3) for j in range(i + 1, 3)
                       for v in (_AXES[i] + _AXES[j], _AXES[i] - _AXES[j],
                                 -_AXES[i] + _AXES[j], -_AXES[i] - _AXES[j])])
_SAME_DIRECTION = np.cos(np.radians(5.0))   # directions closer than this are one
_PARKED = 100.0        # parts taken away are parked this far along x
# The Cursor oracle holds the growing assembly this high (m): parts still lying
# on the floor pass beneath it. The task's next_pair follows the plan for it.
HOLD_LIFT = 0.3


@dataclasses.dataclass(frozen=True)
class Step:
  """One insertion, in the assembled (design) frame.

  The part travels `waypoints` (offsets of its assembled position, from the
  farthest to the goal) in its assembled orientation; the last waypoint is 0.
  """
  part: int
  waypoints: tuple


class _Scene:
  """The furniture in plain MuJoCo, with parts moved in and out of the scene by qpos."""

  def __init__(self, spec, lift):
    self.model = model_format.compile_model(spec)
    physics_settings.configure_model(self.model)
    self.model.geom_margin[:] = 2 * LOOSE   # report near misses, not only overlaps
    self.air = CLEARANCE
    self.data = mujoco.MjData(self.model)
    self.lift = np.array([0.0, 0.0, lift])
    self.body = [mujoco.mj_name2id(self.model, mujoco.mjtObj.mjOBJ_BODY, p.name) for p in spec.parts]
    self.qadr = [self.model.jnt_qposadr[self.model.body_jntadr[b]] for b in self.body]
    self.home = [self.data.qpos[a:a + 3].copy() for a in self.qadr]
    self.bounds = [self._world_box(i, spec.parts[i]) for i in range(len(spec.parts))]
    self.mate_axes = [_mate_axes(spec, i) for i in range(len(spec.parts))]
    self.seated = self._seated_overlaps()

  def _seated_overlaps(self):
    """{(body, body): metres} how deep each pair of parts already overlaps assembled (a
    model may keep overlaps under validation's tolerance, deeper than PENETRATION)."""
    self.place(set(range(len(self.body))))
    mujoco.mj_fwdPosition(self.model, self.data)
    out = {}
    for c in self.data.contact[:self.data.ncon]:
      pair = tuple(sorted((int(self.model.geom_bodyid[c.geom1]), int(self.model.geom_bodyid[c.geom2]))))
      out[pair] = max(out.get(pair, 0.0), -float(c.dist))
    return out

  def _world_box(self, i, part):
    return part.assembled_corners() + self.lift

  def place(self, present):
    for i, adr in enumerate(self.qadr):
      self.data.qpos[adr:adr + 3] = (self.home[i] + self.lift if i in present
                                     else (_PARKED + 5 * i, 0, 0))

  def collides(self, part, offset):
    """Whether `part` moved by `offset` from its assembled pose overlaps the present parts
    (or, farther than `NEAR` from its place, comes within `CLEARANCE` of them)."""
    adr = self.qadr[part]
    self.data.qpos[adr:adr + 3] = self.home[part] + self.lift + offset
    mujoco.mj_fwdPosition(self.model, self.data)
    body = self.body[part]
    limit = self.air if np.linalg.norm(offset) > NEAR else -PENETRATION
    for c in self.data.contact[:self.data.ncon]:
      ends = (self.model.geom_bodyid[c.geom1], self.model.geom_bodyid[c.geom2])
      # Sliding along what it touches, a part may stay as deep in a neighbour as it sits.
      below = self.seated.get(tuple(sorted(map(int, ends))), 0.0) if self.air < 0 else 0.0
      if c.dist < limit - below and body in ends:
        self.data.qpos[adr:adr + 3] = self.home[part] + self.lift
        return True
    self.data.qpos[adr:adr + 3] = self.home[part] + self.lift
    return False

  def path_free(self, part, start, direction, length):
    return not any(self.collides(part, start + s * direction)
                   for s in np.arange(STEP, length + STEP / 2, STEP))

  def clearance(self, part, present, direction, start=np.zeros(3)):
    """How far `part` must travel along `direction` to leave the present parts' bounding box."""
    rest = np.concatenate([self.bounds[i] for i in present if i != part])
    own = self.bounds[part] + start
    return max((rest @ direction).max() - (own @ direction).min(), 0.0) + MARGIN


def _mate_axes(spec, part):
  """Unit directions, both ways along the up axis of each of the part's connectors (in the
  assembled frame), that are neither an axis nor a diagonal the paths already try."""
  body = spec.parts[part]
  tried = np.concatenate([_AXES, _DIAGONALS])
  out = []
  for c in spec.connectors:
    if c.part != body.name:
      continue
    up = body.rot @ np.asarray(c.rot)[:, 2]
    for d in (up, -up):
      d = d / np.linalg.norm(d)
      if (tried @ d).max() < _SAME_DIRECTION and all(o @ d < _SAME_DIRECTION for o in out):
        out.append(d)
  return np.array(out).reshape(-1, 3)


def _exit_path(scene, part, present, tilted=np.zeros((0, 3))):
  """Waypoints (offsets, farthest first) along which `part` leaves the present parts, or None.

  The farthest waypoint is clear of the rest's bounding box across some plane
  (normal to an axis, to the diagonal between two, or to a `tilted` direction),
  so the part can reach it from anywhere on that plane's far side. Shorter paths
  win; straight paths along an axis beat two-leg ones, which beat straight
  diagonal ones, which beat paths along `tilted` directions (straight, then
  a short way along one and sideways out).
  """
  return (_straight_exit(scene, part, present, _AXES)
          or _bent_exit(scene, part, present, _AXES, across_only=True)
          or _straight_exit(scene, part, present, _DIAGONALS)
          or _straight_exit(scene, part, present, tilted)
          or _bent_exit(scene, part, present, tilted, across_only=False))


def _straight_exit(scene, part, present, directions):
  """The shortest free straight exit along one of `directions` (_exit_path's waypoints),
  or None."""
  lengths = [scene.clearance(part, present, d) for d in directions]
  for k in sorted(range(len(lengths)), key=lengths.__getitem__):
    if scene.path_free(part, np.zeros(3), directions[k], lengths[k]):
      return (lengths[k] * directions[k], np.zeros(3))
  return None


def _bent_exit(scene, part, present, directions, across_only):
  """The shortest free two-leg exit (_exit_path's waypoints), or None: a SHORT_MOVE along
  one of `directions`, then out along an axis that does not point down (and, if
  `across_only`, is not along the first leg)."""
  bent = []
  for d in directions:
    for short in SHORT_MOVE:
      if not scene.path_free(part, np.zeros(3), d, short):
        break
      first = short * d
      for side in _AXES:
        if side[2] > -0.5 and not (across_only and abs(side @ d) >= 0.5):
          bent.append((short + scene.clearance(part, present, side, first), first, side))
  for _, first, side in sorted(bent, key=lambda item: item[0]):
    length = scene.clearance(part, present, side, first)
    if scene.path_free(part, first, side, length):
      return (first + length * side, first, np.zeros(3))
  return None


# FurnitureSpec -> {(root, lift): steps}, for as long as the spec lives.
_PLANS = weakref.WeakKeyDictionary()


def plan(spec, root: int, lift: float = 0.15) -> tuple:
  """Insertion steps for every part but `root`, in assembly order; raises SequenceError if stuck.

  Args:
    spec: the furniture's FurnitureSpec (at the size it is built).
    root: index of the part held still.
    lift: metres the assembly is held above the floor.
  Returns:
    A tuple of Step, computed once per spec, root and lift.
  """
  plans = _PLANS.setdefault(spec, {})
  if (root, lift) not in plans:
    plans[root, lift] = _plan(spec, root, lift)
  return plans[root, lift]


def _plan(spec, root, lift):
  scene = _Scene(spec, lift)
  edges = model_format.coinciding_pairs(spec)
  present = set(range(len(spec.parts)))
  removed = []
  while len(present) > 1:
    scene.place(present)
    step = _next_removal(scene, present, root, edges)
    if step is not None:
      removed.append(step)
      present.remove(step.part)
    else:
      names = [spec.parts[p].name for p in sorted(present - {root})]
      raise errors.SequenceError(
          f"{spec.name}: no part of {names} can leave along a free path (straight or two-leg, "
          "along an axis, a diagonal or a connector's up axis, sliding along faces it touches)")
  return tuple(reversed(removed))


def _next_removal(scene, present, root, edges):
  """A part that can leave now: first any that leaves with `LOOSE` air around it (in the
  assembly it goes in last, into open space), then any that just fits."""
  # Among equals, parts with more neighbours leave first: they close the others in.
  order = sorted(present - {root}, key=lambda p: (-sum(p in e for e in edges), -p))
  order = [p for p in order if graph.connected(present - {p}, edges)]
  for air in (LOOSE, CLEARANCE):
    scene.air = air
    for part in order:
      waypoints = _exit_path(scene, part, present)
      if waypoints is not None:
        scene.air = CLEARANCE
        return Step(part, tuple(tuple(float(v) for v in w) for w in waypoints))
  # Closer fits: along the part's own mates' axes, then sliding along what it touches.
  for air in (CLEARANCE, -PENETRATION):
    scene.air = air
    for part in order:
      waypoints = _exit_path(scene, part, present, scene.mate_axes[part])
      if waypoints is not None:
        scene.air = CLEARANCE
        return Step(part, tuple(tuple(float(v) for v in w) for w in waypoints))
  scene.air = CLEARANCE
  return None




def assembly_order(spec, root):
  """Root, then every part in the order of the buildable sequence (part order if the
  sequencer finds none, e.g. for a user's model without free insertion paths); what
  next_pair follows in the CPU and the batched task."""
  try:
    steps = plan(spec, root, HOLD_LIFT)
  except errors.SequenceError as e:
    logging.warning("%s; next_pair follows part order instead", e)
    return (root,) + tuple(i for i in range(len(spec.parts)) if i != root)
  return (root,) + tuple(step.part for step in steps)
