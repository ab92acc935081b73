"""Seats each mated part against its partner along the mate's up axis.

The original connects two parts once their sites come within its distance
tolerance, so some of its files place a site a few millimetres inside, or
short of, where the parts meet. Made to coincide exactly, such parts
interpenetrate (a toy table's legs 3 mm into its top) or leave a gap (one leg
of a table 4 mm short, so that the table rocks). Along each mate of the solved
tree, from the root outwards, the child part, with every part attached beyond
it (less those also mated to parts that stay, when leaving them breaks fewer
mates: see `_moving`), slides along the mate's up axis to where it just
touches its partner: out of a penetration of up to MAX_PUSH, or across a gap
of up to MAX_GAP. The child's site moves with the slide, so the mate still
coincides; a slide that would push the moving parts into a third part is not
made; every slide is reported. A mate that a slide left apart (one closing a
loop, or one to a part that stayed) and that misses by up to SNAP afterwards
has its second site moved onto the first (reported); one that misses by more
is dropped (reported).
"""

import mujoco
import numpy as np

from ikea_suite.design import mjcf_writer

MAX_PUSH = 0.02    # metres: deepest penetration resolved
MAX_GAP = 0.005    # metres: widest gap closed
_TOUCH = 2e-4      # metres: parts closer than this touch
_PRESS = 5e-4      # metres: a penetration this deep means the parts have met
_STEP = 5e-4       # metres: scan step before bisection
_REACH = 0.05      # metres: distances are measured up to this
_MEET = 1e-4       # metres: loop sites this close meet
SNAP = 0.015       # metres: a loop site that misses by up to this moves onto its partner


class _Scene:
  """The furniture in plain MuJoCo, each part movable through its free joint."""

  def __init__(self, furniture):
    files = mjcf_writer.model_files(furniture)
    xml = files.pop(f"{furniture.name}.xml").decode()
    self.model = mujoco.MjModel.from_xml_string(xml, files)
    self.data = mujoco.MjData(self.model)
    mujoco.mj_kinematics(self.model, self.data)
    self.geoms = {}
    for g in range(self.model.ngeom):
      body = self.model.geom_bodyid[g]
      if body and (self.model.geom_contype[g] or self.model.geom_conaffinity[g]):
        name = mujoco.mj_id2name(self.model, mujoco.mjtObj.mjOBJ_BODY, body)
        self.geoms.setdefault(name, []).append(g)

  def _qpos(self, part):
    body = mujoco.mj_name2id(self.model, mujoco.mjtObj.mjOBJ_BODY, part)
    return self.model.jnt_qposadr[self.model.body_jntadr[body]]

  def move(self, parts, shift):
    for part in parts:
      adr = self._qpos(part)
      self.data.qpos[adr:adr + 3] += shift
    mujoco.mj_kinematics(self.model, self.data)

  def distance(self, part_a, part_b):
    """Signed distance between two parts' collision geoms (negative: penetration)."""
    fromto = np.zeros(6)
    return min(mujoco.mj_geomDistance(self.model, self.data, a, b, _REACH, fromto)
               for a in self.geoms.get(part_a, []) for b in self.geoms.get(part_b, []))


def _first(gap, hit, limit):
  """The least shift s in (0, limit] along either sign where hit(gap(s)) holds, bisected
  to within 1e-6 m; None when there is none."""
  best = None
  for sign in (1.0, -1.0):
    s = 0.0
    while s < limit:
      s = min(s + _STEP, limit)
      if hit(gap(sign * s)):
        lo, hi = s - _STEP, s
        while hi - lo > 1e-6:
          mid = (lo + hi) / 2
          lo, hi = (lo, mid) if hit(gap(sign * mid)) else (mid, hi)
        if best is None or hi < abs(best):
          best = sign * hi
        break
  return best


def _slide(scene, parent, moving, axis):
  """(shift, start): the shift along `axis` that seats `moving[0]` on `parent` (0 when
  none is needed or none fits), and their signed distance before it.

  Penetrating parts move out, the least way that clears them. Separate parts move
  the least way along the axis that makes them touch: the travel to where they
  would first press `_PRESS` into each other, less that. Parts already touching
  side by side (distance 0) slide along the axis until they meet this way too.
  """
  def gap(s):
    scene.move(moving, s * axis)
    d = scene.distance(parent, moving[0])
    scene.move(moving, -s * axis)
    return d
  start = gap(0.0)
  if start < -_PRESS:
    shift = _first(gap, lambda d: d >= 0.0, MAX_PUSH)
  else:
    shift = _first(gap, lambda d: d < -_PRESS, MAX_GAP + _PRESS)
    if shift is not None:
      shift -= np.sign(shift) * _PRESS
      if abs(shift) < _TOUCH:
        shift = None
  return (0.0 if shift is None else shift), start


def seat(furniture, edges, loops):
  """Slides mated parts until they touch (see the module docstring); edits `furniture`.

  Args:
    furniture: the Blueprint, parts at their solved assembled poses.
    edges: (parent part, parent connector, child part, child connector) names of the
      solved tree's mates, root outwards.
    loops: (part, connector, part, connector) names of the kept mates outside the tree.

  Returns:
    (notes, dropped): one sentence per slide, moved or dropped loop site, and the
    (connector, connector) names of the loop mates dropped.
  """
  parts = {p.name: p for p in furniture.parts}
  children = {}
  for parent, _, child, _ in edges:
    children.setdefault(parent, []).append(child)
  def subtree(part):
    out = [part]
    for child in children.get(part, []):
      out += subtree(child)
    return out
  mates = [(a, b) for a, _, b, _ in list(edges) + list(loops)]
  scene = _Scene(furniture)
  notes = []
  for index, (parent, parent_site, child, child_site) in enumerate(edges):
    part = parts[child]
    site = next(c for c in part.connectors if c.name == child_site)
    axis = part.rot @ site.rot[:, 2]
    moving, staying = _moving(child, subtree, mates, index)
    shift, start = _slide(scene, parent, moving, axis)
    if staying and abs(shift) > SNAP:   # the mates left behind could not be met again
      moving, staying = subtree(child), []
      shift, start = _slide(scene, parent, moving, axis)
    if shift == 0.0:
      continue
    others = [name for name in parts if name not in moving and name != parent]
    before = _clearance(scene, moving, others)
    scene.move(moving, shift * axis)
    if _clearance(scene, moving, others) < min(before, 0.0) - _TOUCH:
      scene.move(moving, -shift * axis)   # the slide would push into another part
      continue
    for name in moving:
      parts[name].pos = parts[name].pos + shift * axis
    site.pos = site.pos - shift * site.rot[:, 2]
    how = ("out of a {:.1f} mm penetration".format(-start * 1000) if start < -_PRESS
           else "to close a gap")
    stay = (f"; {staying} stayed, as they are mated to parts that do not move" if staying
            else "")
    notes.append(f"part {child!r} slid {abs(shift) * 1000:.1f} mm along the up axis of site "
                 f"{child_site!r} to touch {parent!r} ({how}); the site moved with it{stay}")
  dropped = []
  # Tree mates too: one to a part that stayed behind a slide is apart now.
  for part_a, site_a, part_b, site_b in list(edges) + list(loops):
    a = next(c for c in parts[part_a].connectors if c.name == site_a)
    b = next(c for c in parts[part_b].connectors if c.name == site_b)
    world_a = parts[part_a].pos + parts[part_a].rot @ a.pos
    gap = float(np.linalg.norm(world_a - parts[part_b].pos - parts[part_b].rot @ b.pos))
    if gap <= _MEET:
      continue
    if gap <= SNAP:
      b.pos = parts[part_b].rot.T @ (world_a - parts[part_b].pos)
      notes.append(f"site {site_b!r} moved {gap * 1000:.1f} mm to meet {site_a!r} after the "
                   "slides")
      continue
    parts[part_a].connectors.remove(a)
    parts[part_b].connectors.remove(b)
    dropped.append((site_a, site_b))
    notes.append(f"sites {site_a!r} and {site_b!r} are {gap * 1000:.1f} mm apart after the "
                 "slides; dropped")
  return notes, dropped


def _broken(moving, mates, own):
  """How many mates other than mates[own] join a moving part to one that stays."""
  return sum((a in moving) != (b in moving) for k, (a, b) in enumerate(mates) if k != own)


def _moving(child, subtree, mates, own):
  """(moving, staying): the parts that slide with `child` along the tree mate mates[own].

  Its whole subtree slides unless a part of it is also mated (a loop) to a part
  outside: a rigid slide would pull that mate apart. Such parts, and what hangs
  from them, then stay, when that breaks fewer mates than moving the whole subtree
  (a back panel mated to both sides slides alone, not with the far side and the
  shelves that side carries).
  """
  full = subtree(child)
  held = set(full)
  while True:
    loose = [p for a, b in mates for p, q in ((a, b), (b, a))
             if p in held and p != child and q not in held]
    if not loose:
      break
    held -= set(subtree(loose[0]))
  if len(held) == len(full) or _broken(held, mates, own) >= _broken(set(full), mates, own):
    return full, []
  return [p for p in full if p in held], [p for p in full if p not in held]


def _clearance(scene, moving, others):
  """Least signed distance between the moving parts and the others (m)."""
  return min((scene.distance(a, b) for a in moving for b in others), default=_REACH)
