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

- collision boxes (along any of their axes) and cylinders (along their axis)
  are trimmed only when the contact normal lies within acos(_ALIGN) of that
  axis; a convex collision mesh (a part that collides through its own mesh or
  its coacd pieces) is cut flat across the contact normal, so it stays convex
  (a mesh that is also the part's visible shape keeps it to show, and a trimmed
  copy collides); of two candidates the one longer along the normal is trimmed
  (the smaller relative change);
- the _AIR left between the trimmed face and its neighbour lets a part slide
  past the other along that face as it goes in (the sequencer keeps
  sequence.CLEARANCE of air around a sliding part; trimmed to bare contact, a
  back panel between two sides could not leave the assembly in any direction);
- at most MAX_TRIM off each face, and never more than half the geom's extent
  along an axis;
- the trimmed geom keeps its mass (its density rises by the volume lost), so
  every part weighs what it did; visual meshes do not change.

An overlap is not trimmed when the file's own poses fit the two parts together
another way: there they touch (within _FILE_TOUCH) without overlapping, but in
a pose relative to each other that differs from the one their connectors give
(by more than seat.SNAP or _SAME_TURN). Then a connector pairs them against the
file's geometry (chair_ingolf_0650's sides name 'front' the sites at their back
end, so its back enters the seat by 12 mm), and a trim would hide that.

Overlaps that cannot be trimmed are left, with a note naming the parts and why,
and validation then reports them.
"""

import dataclasses

import mujoco
import numpy as np
import trimesh

from ikea_suite import geometry
from ikea_suite import physics_settings
from ikea_suite.assembly import sequence
from ikea_suite.design import construction
from ikea_suite.design import mjcf_writer
from ikea_suite.design import part_geoms
from ikea_suite.design import validate
from ikea_suite.design.original import seat

MAX_TRIM = 0.015    # metres: the most taken off one face (the deepest data overlap seen: 10.8 mm)
_AIR = sequence.CLEARANCE + 5e-4   # metres left between a trimmed face and its neighbour
_ALIGN = 0.95       # cosine between contact normal and the trimmed axis (about 18 degrees)
_ROUNDS = 10        # overlap sweeps; a trim can leave a shallower contact of the same pair
_GEOM = "_geom"     # mjcf_writer names geom i of part P 'P_geom{i}'
_FILE_TOUCH = 0.005   # metres: parts this close in the file's poses are fitted together there
_SAME_TURN = np.radians(5.0)   # parts turned less than this from the file's relative pose


def _compile(furniture):
  files = mjcf_writer.model_files(furniture)
  xml = files.pop(f"{furniture.name}.xml").decode()
  model = mujoco.MjModel.from_xml_string(xml, files)
  physics_settings.configure_model(model)   # the contact settings validation uses
  return model, mujoco.MjData(model)


def _fitted_otherwise(furniture, file_poses, part_a, part_b):
  """(gap, offset, turn) when the file's own poses fit part_b to part_a another way: there
  they are at most _FILE_TOUCH apart and not overlapping, in a relative pose `offset`
  metres and `turn` radians from the assembled one; else None."""
  if not file_poses or part_a not in file_poses or part_b not in file_poses:
    return None
  parts = {p.name: p for p in furniture.parts}
  (fa, ra), (fb, rb) = file_poses[part_a], file_poses[part_b]
  a, b = parts[part_a], parts[part_b]
  rel_rot = ra.T @ rb
  pos = a.pos + a.rot @ (ra.T @ (fb - fa))   # part_b where the file has it, part_a staying
  rot = a.rot @ rel_rot
  offset = float(np.linalg.norm(pos - b.pos))
  turn = float(np.linalg.norm(geometry.mat_to_axis_angle(rot @ b.rot.T)))
  if offset <= seat.SNAP and turn <= _SAME_TURN:
    return None
  model, data = _compile(furniture)
  body = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_BODY, part_b)
  adr = model.jnt_qposadr[model.body_jntadr[body]]
  data.qpos[adr:adr + 3], data.qpos[adr + 3:adr + 7] = pos, geometry.mat_to_quat(rot)
  mujoco.mj_kinematics(model, data)
  geoms = {n: [g for g in range(model.ngeom) if model.geom_bodyid[g] == model.body(n).id
               and (model.geom_contype[g] or model.geom_conaffinity[g])] for n in (part_a, part_b)}
  gap = min(mujoco.mj_geomDistance(model, data, i, j, _FILE_TOUCH * 2, np.zeros(6))
            for i in geoms[part_a] for j in geoms[part_b])
  if -validate.PENETRATION_TOL <= gap <= _FILE_TOUCH:
    return gap, offset, turn
  return None


def _overlaps(furniture):
  """(depth, (part, index), (part, index), normal) of the deepest contact of each pair of
  geoms of different parts overlapping by more than PENETRATION_TOL, deepest first;
  the world normal points from the first geom to the second."""
  model, data = _compile(furniture)
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


def _mesh_face(furniture, part, geom, toward):
  """(local unit normal, extent): the direction, in the mesh's frame, in which a convex
  collision mesh's overlapping face points (the world direction `toward`), and the
  mesh's extent along it; None when the geom is not a colliding mesh."""
  if geom.type != "mesh" or not geom.collide:
    return None
  local = (part.rot @ geom.rot).T @ toward
  local = local / np.linalg.norm(local)
  heights = furniture.meshes[geom.mesh].vertices @ local
  return local, float(heights.max() - heights.min())


def _cut_mesh(furniture, part, geom, normal, amount, trimmed):
  """Cuts `amount` off a convex collision mesh across its local `normal`, keeping its mass.
  A mesh that is also seen stays as it is, to be seen only; the cut copy collides.
  Returns the geom that now collides."""
  mesh = furniture.meshes[geom.mesh]
  height = mesh.vertices @ normal
  below = height - (height.max() - amount)   # <= 0: kept
  first, second = below[mesh.edges_unique[:, 0]], below[mesh.edges_unique[:, 1]]
  crossing = (first < 0) != (second < 0)
  ends = mesh.vertices[mesh.edges_unique[crossing]]
  t = (first[crossing] / (first[crossing] - second[crossing]))[:, None]
  # The piece is convex: the hull of what stays and of where its edges cross the plane
  # is the piece cut flat.
  cut = trimesh.convex.convex_hull(np.concatenate([mesh.vertices[below <= 0],
                                                  ends[:, 0] + t * (ends[:, 1] - ends[:, 0])]))
  if geom.visible:
    colliding = dataclasses.replace(geom, visible=False)
    geom.collide, geom.construction = False, None
    part.geoms.append(colliding)
    trimmed[id(colliding)] = trimmed.pop(id(geom), {})
    geom = colliding
  geom.mesh = part_geoms.register_mesh(furniture, cut, geom.mesh.rsplit("_", 1)[0] + "_trim")
  if geom.construction is not None:
    geom.construction = construction.solid(
        geom.construction.density * abs(mesh.volume) / abs(cut.volume),
        f"{geom.construction.name}, denser by the volume its collision trim removed")
  faces = trimmed.setdefault(id(geom), {})
  key = tuple(np.round(normal, 1))
  faces[key] = faces.get(key, 0.0) + amount
  return geom


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


def trim(furniture, file_poses=None):
  """Clears data overlaps between parts' collision primitives (see the module docstring).

  Args:
    furniture: the Blueprint, parts at their seated assembled poses; edited in place.
    file_poses: part name -> (pos, rot) as the file writes the part, in the same part
      frame; None skips the check against them.

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
      fitted = _fitted_otherwise(furniture, file_poses, part_a, part_b)
      if fitted is not None:
        refused[frozenset((part_a, part_b))] = depth
        notes.append(_misfit(part_a, i, part_b, j, depth, *fitted))
        continue
      options = []
      for name, index, toward in ((part_a, i, normal), (part_b, j, -normal)):
        part, geom = parts[name], parts[name].geoms[index]
        face = _mesh_face(furniture, part, geom, toward)
        if face is not None:
          local, extent = face
          amount = depth + _AIR
          done = trimmed.get(id(geom), {}).get(tuple(np.round(local, 1)), 0.0)
          if done + amount <= MAX_TRIM and amount <= extent / 2:
            options.append((extent, name, index, local, None, amount))
          continue
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
      geom = parts[name].geoms[index]
      kind = "convex mesh" if geom.type == "mesh" else geom.type
      if geom.type == "mesh":
        kept = " (its visible mesh unchanged)" if geom.visible else ""
        _cut_mesh(furniture, parts[name], geom, k, amount, trimmed)
        how = f"cut {amount * 1000:.1f} mm across the overlap{kept}"
      else:
        _cut(parts[name], geom, k, sign, amount, trimmed)
        how = f"trimmed {amount * 1000:.1f} mm"
      notes.append(f"collision {kind} '{name}{_GEOM}{index}' of part {name!r} {how} where "
                   f"the file's own collision shapes overlap part {other!r} by "
                   f"{depth * 1000:.1f} mm in the assembled pose ({_AIR * 1000:.1f} mm of air "
                   "left); the part keeps its mass")
      made = True
      cut.update({(part_a, i), (part_b, j)})
    if not made:
      break
  return notes


def _misfit(part_a, i, part_b, j, depth, gap, offset, turn):
  return (f"parts {part_a!r} and {part_b!r} overlap by {depth * 1000:.1f} mm in the assembled "
          f"pose ('{part_a}{_GEOM}{i}', '{part_b}{_GEOM}{j}'); not trimmed: in the file's own "
          f"poses they fit together {gap * 1000:.1f} mm apart, {offset * 1000:.0f} mm and "
          f"{np.degrees(turn):.0f} deg from where their connectors put them, so a connector "
          "pairs them in a way the file's geometry does not support (sites named for the "
          "wrong end?)")


def _refusal(parts, part_a, i, part_b, j, depth):
  geoms = [parts[part_a].geoms[i], parts[part_b].geoms[j]]
  kinds = {g.type for g in geoms}
  if not kinds & {"box", "cylinder", "mesh"}:
    why = f"only collision boxes, cylinders and convex meshes are trimmed, these are {sorted(kinds)}"
  elif depth > MAX_TRIM:
    why = f"deeper than the {MAX_TRIM * 1000:.0f} mm a trim may take"
  else:
    why = ("no box or cylinder axis lies along the overlap, or the trim would take more "
           f"than {MAX_TRIM * 1000:.0f} mm or half the geom's extent along it")
  return (f"parts {part_a!r} and {part_b!r} overlap by {depth * 1000:.1f} mm in the assembled "
          f"pose ('{part_a}{_GEOM}{i}', '{part_b}{_GEOM}{j}'); not trimmed: {why}")
