"""Matches an original model's connector sites and solves its assembled pose from them.

The original's body poses are not always the assembled layout (some mated sites
sit centimetres apart or face opposite ways in the file), so the assembled pose
is derived from the connector frames alone:

0. A file whose layout is a complete assembly (every connector site meets exactly
   one site on another part) that its names contradict is read as laid out:
   chair_ingolf_0650's sides name 'front' the sites at their back ends. Each
   site takes the type and twist of the pair it is laid in (reported).
1. Every connector site becomes one of our connectors: type 'A-B', mates
   'B-A', frame turned so that the original's +y forward becomes our +x
   (same up axis z). The twists of a type pair are unified over all its sites
   and closed under negation, as our format needs both mates to list the same
   twists and either may be the first of a pair.
2. Sites are matched greedily, each site used once: a site `A-B` mates an
   unused `B-A` on another part. Pairs that agree with more of the other
   candidate pairs between the same two parts go first (placing the second
   part through the pair makes those sites meet too), then the closest
   (distance between the sites in the file's poses, opposed up axes counted
   as 10 cm). Some files write two parts facing the other way, so that the
   pairs closest in the file cannot all hold at once.
3. From a root part (the one with the most matches), mates are chained: each
   new part is placed so that its site coincides with its partner, up axes
   equal and forwards one allowed twist apart (the twist closest to the file's
   relative orientation). The next part placed is the one whose placement
   makes the most of its mates to already placed parts meet, then the one
   turned least from its orientation in the file, so that a site written
   facing the wrong way does not decide where its part goes.
4. Matches that close a loop are kept when they coincide within 0.1 mm;
   when their frames agree but they miss by up to 15 mm (the original
   connects sites within a tolerance), the second site is moved onto the
   first (reported); otherwise they are dropped (reported).

Sites left without a partner are dropped and reported; parts that cannot be
reached from the root make the model unconvertible (ConversionError naming
the parts and the unpartnered sites).
"""

import collections
import dataclasses

import numpy as np

from ikea_suite import errors
from ikea_suite import geometry
from ikea_suite.design.original import names
from ikea_suite.design.original import reader
from ikea_suite.design.original import seat

# The original's site frame has +y forward; ours +x. Both have +z up.
Y_FORWARD_TO_X = geometry.rot_z(np.pi / 2)
_OPPOSED_UP_COST = 0.05   # metres per unit of (1 - cos) between up axes, when matching
_CLOSE_POS = 1e-4         # metres: a loop match is kept when its sites meet this closely
_CLOSE_COS = 0.9999       # and their axes agree to this cosine
_SNAP_POS = seat.SNAP     # metres: a loop site that misses by up to this is moved onto its
                          # partner (the original connects sites within a tolerance)
_MEET_POS = 0.002         # metres: sites this close in the file's poses meet there


@dataclasses.dataclass
class Connector:
  """A connector site in our convention."""
  site: str               # the original site name
  body: str
  type: str
  mates: str
  twists_deg: tuple       # () = any twist
  pos: np.ndarray         # part frame
  rot: np.ndarray         # part frame; z up, x forward


@dataclasses.dataclass
class Assembly:
  """The solved assembled layout of an original model."""
  root: str
  poses: dict             # body -> (pos (3,), rot (3, 3)), the root at its file pose
  connectors: list        # the matched connectors (the ones to write)
  pairs: list             # (site, site) of every mated pair kept
  tree: list              # (parent, child) Connector of each mate placing a part, root outwards
  notes: list             # repairs: dropped sites, unified twists, dropped welds and loops


def _connectors(model):
  out = []
  for body in model.bodies:
    for site in body.sites:
      if names.is_connector(site.name):
        parsed = names.parse(site.name, model.path)
        out.append(Connector(site.name, body.name, parsed.type, parsed.mate_type,
                             parsed.twists_deg, site.pos, site.rot @ Y_FORWARD_TO_X))
  if not out:
    raise errors.ConversionError(model.path, "<worldbody>",
                                 "no connector sites (names with 'conn_site'; an incomplete file)")
  return out


def _closed_twists(lists):
  if any(not t for t in lists):
    return ()
  return tuple(sorted({round(s * a % 360.0, 6) % 360.0 for t in lists for a in t for s in (1, -1)}))


def _unify_twists(connectors, notes):
  by_pair = collections.defaultdict(list)
  for c in connectors:
    by_pair[frozenset((c.type, c.mates))].append(c)
  for key, members in by_pair.items():
    twists = _closed_twists([c.twists_deg for c in members])
    if any(c.twists_deg != twists for c in members):
      written = sorted({c.twists_deg for c in members})
      notes.append(f"twists of {' and '.join(sorted(key))} unified to "
                   f"{list(twists) or 'any'} (written: {[list(t) or 'any' for t in written]})")
    for c in members:
      c.twists_deg = twists


def _world(pose, c):
  pos, rot = pose
  return pos + rot @ c.pos, rot @ c.rot


def _twist_deg(rot_a, rot_b):
  """The turn (degrees, in [0, 360)) about a's up axis from a's forward to b's."""
  m = rot_a.T @ rot_b
  return round(float(np.degrees(np.arctan2(m[1, 0], m[0, 0]))) % 360.0, 6) % 360.0


def _relabel_by_layout(connectors, file_poses, path, notes):
  """Renames the sites of a file whose layout is a complete assembly that its names contradict.

  When every connector site meets exactly one site on another part in the file's poses
  (within _MEET_POS, up axes equal) and some of those pairs the names do not mate, the
  layout is the designer's intent: every pair gets the types and the twist it meets at
  (chair_ingolf_0650: by name its sides are reversed and its back enters the seat by
  12 mm; as laid out it is sound).
  """
  world = [_world(file_poses[c.body], c) for c in connectors]
  partner = {}
  for i, (pos, rot) in enumerate(world):
    near = [j for j, (q, r) in enumerate(world) if connectors[j].body != connectors[i].body
            and np.linalg.norm(pos - q) <= _MEET_POS and rot[:, 2] @ r[:, 2] >= _CLOSE_COS]
    if len(near) != 1:
      return
    partner[i] = near[0]
  if any(partner[j] != i for i, j in partner.items()):
    return
  if all(connectors[i].mates == connectors[j].type for i, j in partner.items()):
    return   # names agree: a twist off the allowed ones is the file's loose placement
  taken = {c.site for c in connectors}
  for i, j in partner.items():
    a, b = connectors[i], connectors[j]
    twist = _twist_deg(world[i][1], world[j][1])
    allowed = not a.twists_deg or any(abs((twist - t + 180.0) % 360.0 - 180.0) < 0.5
                                      for t in a.twists_deg)
    group, other = a.type.split("-")[0], b.type.split("-")[0]
    if a.type == f"{group}-{other}" and allowed:
      continue
    twists = a.twists_deg and tuple(sorted({*a.twists_deg, round(twist)}))
    site = (f"{group}-{other},{','.join(f'{t:g}' for t in twists)},"
            f"{names.CONN_MARK}{names.parse(a.site, path).tag}")
    while site in taken:
      site += "r"
    taken.add(site)
    notes.append(f"site {a.site!r} on part {a.body!r} read as {site!r}: the file lays it on "
                 f"{b.site!r} of part {b.body!r}, turned {twist:g} degrees, and every "
                 "connector site of the file meets exactly one other, so the layout is kept")
    a.site, a.type, a.mates, a.twists_deg = site, f"{group}-{other}", f"{other}-{group}", twists


def _meets(a, b, poses):
  """Whether two sites meet in the given poses, within the tolerance a loop site is moved."""
  return _gap(a, b, poses) <= _SNAP_POS and _aligned(a, b, poses)


def _support(candidates, connectors, file_poses):
  """For each candidate pair, how many other candidate pairs between the same two parts
  meet when the second part is placed through it (the first at its file pose)."""
  between = collections.defaultdict(list)
  for _, i, j in candidates:
    between[(connectors[i].body, connectors[j].body)].append((i, j))
  support = {}
  for (body_a, body_b), pairs in between.items():
    rel_file = file_poses[body_a][1].T @ file_poses[body_b][1]
    for i, j in pairs:
      poses = {body_a: file_poses[body_a]}
      poses[body_b] = _place(file_poses[body_a], connectors[i], connectors[j], rel_file)
      support[(i, j)] = sum(k != i and l != j and _meets(connectors[k], connectors[l], poses)
                            for k, l in pairs)
  return support


def _match(connectors, file_poses, notes):
  """Greedy matching, most supported then closest first; returns index pairs and notes on
  the unmatched sites."""
  candidates = []
  for i, a in enumerate(connectors):
    for j in range(i + 1, len(connectors)):
      b = connectors[j]
      if a.body != b.body and a.mates == b.type:
        (pa, ra), (pb, rb) = _world(file_poses[a.body], a), _world(file_poses[b.body], b)
        cost = np.linalg.norm(pa - pb) + _OPPOSED_UP_COST * (1 - ra[:, 2] @ rb[:, 2])
        candidates.append((cost, i, j))
  support = _support(candidates, connectors, file_poses)
  used, pairs = set(), []
  for _, i, j in sorted(candidates, key=lambda c: (-support[c[1:]], c)):
    if i not in used and j not in used:
      used.update((i, j))
      pairs.append((i, j))
  could = {k for _, i, j in candidates for k in (i, j)}
  unmatched = []
  for k, c in enumerate(connectors):
    if k in used:
      continue
    why = ("every site it could mate is taken by a better pair" if k in could
           else f"no site of type {c.mates!r} on another part")
    unmatched.append(f"site {c.site!r} on part {c.body!r} has no partner: {why}")
  notes.extend(f"{u}; dropped" for u in unmatched)
  return pairs, unmatched


def _best_twist(c_a, c_b, rel_file):
  """The allowed twist closest to the file's relative orientation of the two parts."""
  m = c_a.rot.T @ rel_file @ c_b.rot
  if not c_a.twists_deg:
    return float(np.arctan2(m[1, 0], m[0, 0]))
  return max((np.radians(t) for t in c_a.twists_deg),
             key=lambda t: np.trace(geometry.rot_z(t).T @ m))


def _place(parent_pose, c_a, c_b, rel_file):
  """Pose of c_b's part that puts c_b on c_a (whose part is at parent_pose)."""
  pos_p, rot_p = parent_pose
  rot = rot_p @ c_a.rot @ geometry.rot_z(_best_twist(c_a, c_b, rel_file)) @ c_b.rot.T
  return pos_p + rot_p @ c_a.pos - rot @ c_b.pos, rot


def _gap(c_a, c_b, poses):
  """Distance between two sites in the assembled poses (m)."""
  return float(np.linalg.norm(_world(poses[c_a.body], c_a)[0] - _world(poses[c_b.body], c_b)[0]))


def _aligned(c_a, c_b, poses):
  """Whether two sites' frames agree in the assembled poses: up axes equal, forwards an
  allowed twist apart."""
  ra, rb = _world(poses[c_a.body], c_a)[1], _world(poses[c_b.body], c_b)[1]
  if ra[:, 2] @ rb[:, 2] < _CLOSE_COS:
    return False
  if not c_a.twists_deg:
    return True
  return any(rb[:, 0] @ (ra @ geometry.rot_z(np.radians(t)))[:, 0] > _CLOSE_COS
             for t in c_a.twists_deg)


def _turn(rot_a, rot_b):
  """The angle (rad) between two orientations."""
  return float(np.arccos(np.clip((np.trace(rot_a.T @ rot_b) - 1) / 2, -1.0, 1.0)))


def _chain(root, pairs, connectors, file_poses):
  """Places the parts from the root outwards, one mate at a time.

  Among the mates from a placed to an unplaced part, the one placing its part so that
  the most of that part's mates to placed parts meet goes first, then the one turning
  its part least from the file's relative orientation, then the first found.

  Returns:
    (poses, tree): body -> (pos, rot), and {frozenset(pair): (parent, child) Connector}.
  """
  edges = collections.defaultdict(list)
  for i, j in pairs:
    edges[connectors[i].body].append((i, j))
    edges[connectors[j].body].append((j, i))
  poses, tree, frontier = {root: file_poses[root]}, {}, list(edges[root])
  while True:
    best = None
    for rank, (own, other) in enumerate(frontier):
      body, child = connectors[own].body, connectors[other].body
      if child in poses:
        continue
      rel_file = file_poses[body][1].T @ file_poses[child][1]
      pose = _place(poses[body], connectors[own], connectors[other], rel_file)
      trial = {**poses, child: pose}
      met = sum(_meets(connectors[k], connectors[l], trial) for k, l in edges[child]
                if connectors[l].body in poses)
      key = (-met, _turn(pose[1], poses[body][1] @ rel_file), rank)
      if best is None or key < best[0]:
        best = (key, own, other, child, pose)
    if best is None:
      return poses, tree
    _, own, other, child, poses[child] = best
    tree[frozenset((own, other))] = (connectors[own], connectors[other])
    frontier.extend(edges[child])


def _weld_notes(model, mated_bodies):
  notes, seen = [], set()
  bodies = {b.name for b in model.bodies}
  for a, b in model.welds:
    key = frozenset((a, b))
    if key in seen:
      notes.append(f"dropped duplicate weld between {a!r} and {b!r}")
    elif a not in bodies or b not in bodies:
      notes.append(f"dropped weld between {a!r} and {b!r}: no such part body")
    elif key not in mated_bodies:
      notes.append(f"dropped dead weld between {a!r} and {b!r}: "
                   "the parts share no mated connectors")
    seen.add(key)
  return notes


def solve(model: reader.OriginalModel) -> Assembly:
  """Matches connectors and solves the assembled pose of an original model.

  Args:
    model: an OriginalModel from reader.read.

  Returns:
    An Assembly. The file's own welds are not used (the converted model gets
    one weld per mated pair); duplicate and dead ones are reported in `notes`.

  Raises:
    ConversionError: bad connector names, no connectors, parts without connector
      sites (an incomplete file), or parts unreachable from the root through mating
      connectors (names them and the unpartnered sites).
  """
  notes = []
  connectors = _connectors(model)
  with_sites = {c.body for c in connectors}
  bare = [b.name for b in model.bodies if b.name not in with_sites]
  if bare:   # the file is incomplete: nothing else about its graph can be judged
    raise errors.ConversionError(
        model.path, "<worldbody>", f"parts {bare} have no connector sites, so nothing "
        "can connect them (an incomplete file)")
  file_poses = {b.name: (b.pos, b.rot) for b in model.bodies}
  _relabel_by_layout(connectors, file_poses, model.path, notes)
  _unify_twists(connectors, notes)
  pairs, unmatched = _match(connectors, file_poses, notes)
  degree = collections.Counter(connectors[k].body for pair in pairs for k in pair)
  order = [b.name for b in model.bodies]
  root = max(order, key=lambda name: (degree[name], -order.index(name)))
  poses, tree = _chain(root, pairs, connectors, file_poses)
  unreachable = [name for name in order if name not in poses]
  if unreachable:
    detail = "; ".join(unmatched or ["their connectors only mate among themselves"])
    raise errors.ConversionError(
        model.path, "<worldbody>", f"parts {unreachable} cannot be reached from root part "
        f"{root!r} through mating connectors ({detail})")
  kept = []
  for i, j in pairs:
    a, b = connectors[i], connectors[j]
    gap = _gap(a, b, poses)
    if frozenset((i, j)) in tree or (gap <= _CLOSE_POS and _aligned(a, b, poses)):
      kept.append((i, j))
    elif gap <= _SNAP_POS and _aligned(a, b, poses):
      pos_a = _world(poses[a.body], a)[0]
      b.pos = poses[b.body][1].T @ (pos_a - poses[b.body][0])
      kept.append((i, j))
      notes.append(f"site {b.site!r} moved {gap * 1000:.1f} mm to meet {a.site!r}: the file's "
                   "sites miss each other by that much once the parts are assembled through "
                   "their other connectors")
    else:
      why = (f"{gap * 1000:.1f} mm apart" if gap > _SNAP_POS
             else "their up axes or allowed twists disagree")
      notes.append(f"sites {a.site!r} and {b.site!r} do not meet when the parts are assembled "
                   f"through their other connectors ({why}); dropped")
  notes.extend(_weld_notes(model, {frozenset((connectors[i].body, connectors[j].body))
                                   for i, j in kept}))
  return Assembly(root, poses, [connectors[k] for pair in kept for k in pair],
                  [(connectors[i].site, connectors[j].site) for i, j in kept], list(tree.values()),
                  notes)
