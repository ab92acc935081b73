"""Trims collision primitives that the original's own data leaves overlapping.

Some of the original's files give two parts collision boxes that overlap in
the assembled pose even where their connector sites coincide (a drawer side
10.8 mm into a box's front, a leg panel 6.7 mm into a table's top board). The
original never needed them disjoint: it simulates the parts only apart or
welded. Our validation does (overlaps deeper than PENETRATION_TOL fail), and a
part pressed into another fights its weld. So, after the parts are seated, each
overlap deeper than PENETRATION_TOL is cleared by shortening one of the two
primitives along the contact normal, at the face that overlaps, by the overlap
depth and _AIR more:

- only collision boxes (along any of their axes) and cylinders (along their
  axis) are trimmed, and only when the contact normal lies within
  acos(_ALIGN) of that axis; of two candidates the one longer along the normal
  is trimmed (the smaller relative change);
- the _AIR left between the trimmed face and its neighbour lets a part slide
  past the other along that face as it goes in (the sequencer keeps
  sequence.CLEARANCE of air around a sliding part; trimmed to bare contact, a
  back panel between two sides could not leave the assembly in any direction);
- at most MAX_TRIM off each face, and never more than half the geom's extent
  along an axis;
- the trimmed geom keeps its mass (its density rises by the volume lost), so
  every part weighs what it did; visual meshes do not change.

Overlaps that cannot be trimmed are left, with a note naming the parts and why,
and validation then reports them.
"""

import mujoco
import numpy as np

from ikea_suite import physics_settings
from ikea_suite.assembly import sequence
from ikea_suite.design import construction
from ikea_suite.design import mjcf_writer
from ikea_suite.design import validate

MAX_TRIM = 0.015    # metres: the most taken off one face (the deepest data overlap seen: 10.8 mm)
_AIR = sequence.CLEARANCE + 5e-4   # metres left between a trimmed face and its neighbour
_ALIGN = 0.95       # cosine between contact normal and the trimmed axis (about 18 degrees)
_ROUNDS = 10        # overlap sweeps; a trim can leave a shallower contact of the same pair
_GEOM = "_geom"     # mjcf_writer names geom i of part P 'P_geom{i}'


def _overlaps(furniture):
  """(depth, (part, index), (part, index), normal) of the deepest contact of each pair of
  geoms of different parts overlapping by more than PENETRATION_TOL, deepest first;
  the world normal points from the first geom to the second."""
  files = mjcf_writer.model_files(furniture)
  xml = files.pop(f"{furniture.name}.xml").decode()
  model = mujoco.MjModel.from_xml_string(xml, files)
  physics_settings.configure_model(model)   # the contact settings validation uses
  data = mujoco.MjData(model)
  mujoco.mj_forward(model, data)
  deepest = {}
  for c in data.contact[:data.ncon]:
    body_a, body_b = model.geom_bodyid[c.geom1], model.geom_bodyid[c.geom2]
    if not body_a or not body_b or body_a == body_b or -c.dist <= validate.PENETRATION_TOL:
      continue
    key = (c.geom1, c.geom2)
    if key not in deepest or -c.dist > deepest[key][0]:
      deepest[key] = (-c.dist, np.array(c.frame[:3]))
  out = []
  for (a, b), (depth, normal) in deepest.items():
    names = [mujoco.mj_id2name(model, mujoco.mjtObj.mjOBJ_GEOM, g).rsplit(_GEOM, 1)
             for g in (a, b)]
    out.append((depth, (names[0][0], int(names[0][1])), (names[1][0], int(names[1][1])), normal))
  return sorted(out, key=lambda o: -o[0])


def _axis(part, geom, toward):
  """(local axis, cosine, sign): the geom's trimmable axis nearest the world direction
  `toward` (the way its overlapping face points); None when it has none."""
  if geom.type not in ("box", "cylinder") or not geom.collide:
    return None
  local = (part.rot @ geom.rot).T @ toward
  axes = range(3) if geom.type == "box" else (2,)
  k = max(axes, key=lambda i: abs(local[i]))
  return k, abs(float(local[k])), float(np.sign(local[k]))


def _size_index(geom, k):
  return 1 if geom.type == "cylinder" else k   # a cylinder's half-length is its size[1]


def _cut(part, geom, k, sign, amount, trimmed):
  """Shortens `geom` by `amount` along local axis k at its `sign` face, keeping its mass."""
  i = _size_index(geom, k)
  size = list(geom.size)
  ratio = size[i] / (size[i] - amount / 2)
  size[i] -= amount / 2
  geom.size = tuple(size)
  geom.pos = tuple(np.asarray(geom.pos) - geom.rot[:, k] * sign * amount / 2)
  if geom.construction is not None:
    geom.construction = construction.solid(
        geom.construction.density * ratio,
        f"{geom.construction.name}, denser by the volume its collision trim removed")
  for key in ((id(geom), k, sign), (id(geom), k)):   # per face, and per axis
    trimmed[key] = trimmed.get(key, 0.0) + amount


def trim(furniture):
  """Clears data overlaps between parts' collision primitives (see the module docstring).

  Args:
    furniture: the Blueprint, parts at their seated assembled poses; edited in place.

  Returns:
    One note per trim made and per overlap left (naming the parts and why).
  """
  parts = {p.name: p for p in furniture.parts}
  notes, trimmed, refused = [], {}, {}
  for _ in range(_ROUNDS):
    made, cut = False, set()
    for depth, (part_a, i), (part_b, j), normal in _overlaps(furniture):
      if frozenset((part_a, part_b)) in refused:
        continue
      if {(part_a, i), (part_b, j)} & cut:   # its contacts are stale: measure again first
        continue
      options = []
      for name, index, toward in ((part_a, i, normal), (part_b, j, -normal)):
        part, geom = parts[name], parts[name].geoms[index]
        found = _axis(part, geom, toward)
        if found is None or found[1] < _ALIGN:
          continue
        k, cos, sign = found
        amount = depth / cos + _AIR
        extent = 2 * geom.size[_size_index(geom, k)]
        if (trimmed.get((id(geom), k, sign), 0.0) + amount <= MAX_TRIM
            and trimmed.get((id(geom), k), 0.0) + amount <= extent / 2):
          options.append((extent, name, index, k, sign, amount))
      if not options:
        refused[frozenset((part_a, part_b))] = depth
        notes.append(_refusal(parts, part_a, i, part_b, j, depth))
        continue
      extent, name, index, k, sign, amount = max(options, key=lambda o: o[0])
      other = part_b if name == part_a else part_a
      _cut(parts[name], parts[name].geoms[index], k, sign, amount, trimmed)
      notes.append(f"collision {parts[name].geoms[index].type} '{name}{_GEOM}{index}' of part "
                   f"{name!r} trimmed {amount * 1000:.1f} mm where the file's own collision "
                   f"shapes overlap part {other!r} by {depth * 1000:.1f} mm in the assembled "
                   f"pose ({_AIR * 1000:.1f} mm of air left); the part keeps its mass")
      made = True
      cut.update({(part_a, i), (part_b, j)})
    if not made:
      break
  return notes


def _refusal(parts, part_a, i, part_b, j, depth):
  geoms = [parts[part_a].geoms[i], parts[part_b].geoms[j]]
  kinds = {g.type for g in geoms}
  if not kinds & {"box", "cylinder"}:
    why = f"only collision boxes and cylinders are trimmed, these are {sorted(kinds)}"
  elif depth > MAX_TRIM:
    why = f"deeper than the {MAX_TRIM * 1000:.0f} mm a trim may take"
  else:
    why = ("no box or cylinder axis lies along the overlap, or the trim would take more "
           f"than {MAX_TRIM * 1000:.0f} mm or half the geom's extent")
  return (f"parts {part_a!r} and {part_b!r} overlap by {depth * 1000:.1f} mm in the assembled "
          f"pose ('{part_a}{_GEOM}{i}', '{part_b}{_GEOM}{j}'); not trimmed: {why}")
