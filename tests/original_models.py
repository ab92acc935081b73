"""Writes small furniture models in the original IKEA environment's format, for converter tests.

Nothing here comes from the original's files: meshes are trimesh boxes, the
XML is written from the format's documented facts (top-level bodies, visual
meshes with collisions off, `noviz_collision_*` primitives carrying density,
connector sites named `<A>-<B>,<angles>,conn_site<tag>` with +y forward).
"""

import pathlib

import numpy as np
import trimesh

from ikea_suite.design import shapes

# A site frame whose up (+z) points down and whose forward (+y) points along -y:
# a half turn about x. Legs hang from the top's underside.
DOWN = "0 1 0 0"
CORNERS = [(-0.25, -0.25), (0.25, -0.25), (0.25, 0.25), (-0.25, 0.25)]
TOP_Z, LEG_HALF = 0.42, 0.2


def _meshes(directory, name):
  folder = pathlib.Path(directory) / name
  folder.mkdir(parents=True, exist_ok=True)
  trimesh.creation.box(extents=(600, 600, 40)).export(folder / "top.stl")   # millimetres
  trimesh.creation.box(extents=(1, 1, 1)).export(folder / "unit.stl")      # scaled per axis


def _leg(i, pos, quat="1 0 0 0", extra_site="", site_shift=0.0, density=500):
  return f"""
    <body name="leg{i}" pos="{pos}" quat="{quat}">
      <geom name="leg{i}_mesh" type="mesh" mesh="leg" material="wood" contype="0" conaffinity="0" density="0"/>
      <geom name="noviz_collision_leg{i}_0" type="box" size="0.02 0.02 0.2" rgba="0 0 0 0" density="{density}"/>
      <site name="leg-table,0,90,180,270,conn_site{i}" pos="0 0 {LEG_HALF + site_shift}" quat="{DOWN}" size="0.01"/>
      <site name="leg{i}_bottom_site" pos="0 0 -{LEG_HALF}" size="0.01"/>{extra_site}
    </body>"""


def table(directory, name="table_test", assembled=True, quirks=False, site_shifts=None,
          leg_density=500):
  """A 55 cm side table: a top and four legs, each leg mating any corner of the top.

  Args:
    directory: folder to write `<name>.xml` and `<name>/*.stl` into.
    assembled: False writes the legs centimetres to decimetres from their corners,
      one of them upside down (its up axis opposed to its partner's), and the top
      shifted, as some of the original's files are.
    quirks: adds a non-normalised body and site quaternion, comma-written rgba,
      duplicate and dead welds, a connector site with no partner and initpos data.
    site_shifts: {leg index: metres} moves those legs' connector sites along the leg
      (up: the leg stops short of the top, a gap; down: it pokes into the top), as
      the original's files sometimes place them.
    leg_density: the legs' density in kg/m^3 (some of the original's files give 5).

  Returns:
    The XML path.
  """
  _meshes(directory, name)
  top_pos = f"0 0 {TOP_Z}" if assembled else f"0.1 -0.05 {TOP_Z + 0.08}"
  top_quat = "2 0 0 0" if quirks else "1 0 0 0"
  rgba = "0.9,0.9,0.9,1" if quirks else "0.9 0.9 0.9 1"
  top_sites = "".join(
      f'\n      <site name="table-leg,0,90,180,270,conn_site{i}" pos="{x} {y} -0.02" '
      f'quat="{"0 2 0 0" if quirks and i == 0 else DOWN}" size="0.01"/>'
      for i, (x, y) in enumerate(CORNERS))
  legs = []
  for i, (x, y) in enumerate(CORNERS):
    if assembled:
      pos, quat = f"{x} {y} {LEG_HALF}", "1 0 0 0"
    else:   # displaced by 3 to 25 cm; leg 2 upside down
      pos = f"{x * 1.4 + 0.03 * i} {y * 1.2} {LEG_HALF + 0.02 * i}"
      quat = "0 1 0 0" if i == 2 else "0.9962 0 0 0.0872"
    extra = '\n      <site name="leg-shelf,conn_site9" pos="0 0 0" size="0.01"/>' if quirks and i == 3 else ""
    legs.append(_leg(i, pos, quat, extra, (site_shifts or {}).get(i, 0.0), leg_density))
  welds = ""
  if quirks:
    welds = """
  <equality>
    <weld body1="top" body2="leg0" active="false"/>
    <weld body1="top" body2="leg0" active="false"/>
    <weld body1="leg0" body2="leg1" active="false"/>
  </equality>
  <custom>
    <numeric name="top_initpos" data="0.6 0.3 0.02 1 0 0 0"/>
    <numeric name="leg0_initpos" data="-0.4 0.2 0.02 0.7071 0.7071 0 0"/>
  </custom>"""
  xml = f"""<mujoco model="{name}">
  <asset>
    <mesh name="top" file="{name}/top.stl" scale="0.001 0.001 0.001"/>
    <mesh name="leg" file="{name}/unit.stl" scale="0.04 0.04 0.4"/>
    <texture name="wood" file="../textures/light-wood.png" type="2d"/>
    <material name="wood" texture="wood"/>
  </asset>
  <worldbody>
    <body name="top" pos="{top_pos}" quat="{top_quat}">
      <geom name="top_mesh" type="mesh" mesh="top" rgba="{rgba}" contype="0" conaffinity="0" density="0"/>
      <geom name="noviz_collision_top_0" type="box" size="0.3 0.3 0.02" rgba="0 0 0 0" density="100"/>{top_sites}
      <site name="top_top_site" pos="0 0 0.02" size="0.01"/>
      <site name="top_corner_site1" pos="0.3 0.3 0.02" size="0.01"/>
    </body>{"".join(legs)}
  </worldbody>{welds}
</mujoco>
"""
  path = pathlib.Path(directory) / f"{name}.xml"
  path.write_text(xml)
  return path


def disconnected(directory, name="shelf_broken", bare=False):
  """Three boards where the third's only site mates a group no other part has
  (with `bare`, the third has no connector site at all, as some original parts have)."""
  _meshes(directory, name)
  bodies = []
  for i, (part, site) in enumerate((("a", "a-b,conn_site1"), ("b", "b-a,conn_site1"),
                                    ("c", "" if bare else "c-d,0,180,conn_site1"))):
    site_xml = f'\n      <site name="{site}" pos="0.3 0 0" size="0.01"/>' if site else ""
    bodies.append(f"""
    <body name="{part}" pos="{i * 0.7} 0 0.02">
      <geom name="noviz_collision_{part}_0" type="box" size="0.3 0.3 0.02" density="100"/>{site_xml}
    </body>""")
  path = pathlib.Path(directory) / f"{name}.xml"
  path.write_text(f'<mujoco model="{name}">\n  <worldbody>{"".join(bodies)}\n  </worldbody>\n</mujoco>\n')
  return path


def stool_with_mesh_collision(directory, name="stool_mesh"):
  """A seat and two inverted-T legs that collide through their own meshes (no primitives).

  The seat mesh is convex (it collides as itself); each leg mesh is concave (a
  post on a foot), so the converter decomposes it with coacd.
  """
  folder = pathlib.Path(directory) / name
  folder.mkdir(parents=True, exist_ok=True)
  trimesh.creation.box(extents=(400, 300, 30)).export(folder / "seat.stl")
  leg = shapes.extrude_polygon(shapes.t_profile(0.3, 0.4, 0.04, 0.04), 0.04)   # foot along x
  leg.apply_transform(trimesh.transformations.rotation_matrix(np.pi / 2, (0, 0, 1)))
  leg.export(folder / "leg.stl")
  legs = "".join(f"""
    <body name="leg{i}" pos="{x} 0 0.2">
      <geom name="leg{i}_mesh" type="mesh" mesh="leg" rgba="0.3 0.2 0.1 1" density="600"/>
      <site name="leg-seat,0,180,conn_site{i}" pos="0 0 0.2" quat="{DOWN}" size="0.01"/>
    </body>""" for i, x in enumerate((-0.15, 0.15)))
  path = pathlib.Path(directory) / f"{name}.xml"
  path.write_text(f"""<mujoco model="{name}">
  <asset>
    <mesh name="seat" file="{name}/seat.stl" scale="0.001 0.001 0.001"/>
    <mesh name="leg" file="{name}/leg.stl"/>
  </asset>
  <worldbody>
    <body name="seat" pos="0 0 0.415">
      <geom name="seat_mesh" type="mesh" mesh="seat" rgba="0.9 0.8 0.6 1" density="500"/>
      <site name="seat-leg,0,180,conn_site1" pos="-0.15 0 -0.015" quat="{DOWN}" size="0.01"/>
      <site name="seat-leg,0,180,conn_site2" pos="0.15 0 -0.015" quat="{DOWN}" size="0.01"/>
    </body>{legs}
  </worldbody>
</mujoco>
""")
  return path


def two_boards(directory, twists_a="", twists_b="", yaw_b=0.0, name="boards"):
  """A board with a second board standing on it, joined by one site pair at the top's centre.

  Args:
    twists_a, twists_b: the angle fields of the two site names, e.g. ',90' (empty: any twist).
    yaw_b: degrees the upper board is turned about z in the file.
  """
  half = np.radians(yaw_b) / 2
  quat = f"{np.cos(half):.9f} 0 0 {np.sin(half):.9f}"
  path = pathlib.Path(directory) / f"{name}.xml"
  path.parent.mkdir(parents=True, exist_ok=True)
  path.write_text(f"""<mujoco model="{name}">
  <worldbody>
    <body name="lower" pos="0 0 0.02">
      <geom name="noviz_collision_lower_0" type="box" size="0.3 0.2 0.02" density="500"/>
      <site name="lower-upper{twists_a},conn_site1" pos="0 0 0.02" size="0.01"/>
    </body>
    <body name="upper" pos="0 0 0.07" quat="{quat}">
      <geom name="noviz_collision_upper_0" type="box" size="0.1 0.05 0.03" density="500"/>
      <site name="upper-lower{twists_b},conn_site1" pos="0 0 -0.03" size="0.01"/>
    </body>
  </worldbody>
</mujoco>
""")
  return path


def bookcase(directory, name="bookcase_loops", assembled=True, bad_loop=0.0, poke=0.0,
             flip=None):
  """Two side panels and three shelves, each shelf mating both sides: the graph has loops.

  Site up axes point out of the shelf ends (+-x); numbered groups as in many of
  the original's files ('0-1' mates '1-0'). With `assembled` False every part
  sits a few centimetres from its place. `bad_loop` (metres) raises the right
  side's top shelf site by that much, so that mate misses when its loop closes.
  `poke` (metres) moves the middle shelf's left site that far in along the shelf,
  so that the shelf pokes into the left side when the sites coincide. `flip` (a
  shelf index) writes the left side's site for that shelf with its up axis the wrong
  way (+x), as one of the original's bookcases does: no pose of the shelf meets both
  its mates.
  """
  left, right = "0.7071068 0 -0.7071068 0", "0.7071068 0 0.7071068 0"   # up -x, up +x
  heights = (0.1, 0.4, 0.7)
  def off(i):
    return (0.0, 0.0, 0.0) if assembled else (0.02 * i, -0.03 * i, 0.015 * (i % 2))
  bodies = []
  for s, (x, quat, inner) in enumerate(((-0.4, left, 0.01), (0.4, right, -0.01))):
    sites = "".join(f'\n      <site name="{s}-2,0,180,conn_site{k}" pos="{inner} 0 '
                    f'{z - 0.4 + (bad_loop if s == 1 and k == 2 else 0)}" '
                    f'quat="{right if s == 0 and k == flip else quat}" size="0.01"/>'
                    for k, z in enumerate(heights))
    dx, dy, dz = off(s + 1)
    bodies.append(f"""
    <body name="side{s}" pos="{x + dx} {dy} {0.4 + dz}">
      <geom name="noviz_collision_side{s}_0" type="box" size="0.01 0.15 0.4" density="600"/>{sites}
    </body>""")
  for k, z in enumerate(heights):
    dx, dy, dz = off(k + 3)
    bodies.append(f"""
    <body name="shelf{k}" pos="{dx} {dy} {z + dz}">
      <geom name="noviz_collision_shelf{k}_0" type="box" size="0.39 0.15 0.01" density="600"/>
      <site name="2-0,0,180,conn_site{2 * k}" pos="{-0.39 + (poke if k == 1 else 0)} 0 0" quat="{left}" size="0.01"/>
      <site name="2-1,0,180,conn_site{2 * k + 1}" pos="0.39 0 0" quat="{right}" size="0.01"/>
    </body>""")
  path = pathlib.Path(directory) / f"{name}.xml"
  path.parent.mkdir(parents=True, exist_ok=True)
  path.write_text(f'<mujoco model="{name}">\n  <worldbody>{"".join(bodies)}\n  </worldbody>\n</mujoco>\n')
  return path


def bench_with_euler_rail(directory, name="bench_euler", compiler=""):
  """A bench: two upright legs joined by a crossbar cylinder laid along y by a geom `euler`.

  The original's files write such eulers in radians (their base.xml compiles with
  angle="radian"). Read as degrees, the crossbar would stand upright through the seat.

  Args:
    compiler: an optional `<compiler .../>` element; with angle="degree" the file
      writes the same turn as 90 degrees.
  """
  turn = "90" if 'angle="degree"' in compiler else "1.5707963"
  legs = "".join(f"""
    <body name="leg{i}" pos="0 {y} 0.2">
      <geom name="noviz_collision_leg{i}_0" type="box" size="0.03 0.02 0.2" density="500"/>
      <site name="leg-seat,0,180,conn_site{i}" pos="0 0 0.2" size="0.01"/>
    </body>""" for i, y in enumerate((-0.2, 0.2)))
  path = pathlib.Path(directory) / f"{name}.xml"
  path.parent.mkdir(parents=True, exist_ok=True)
  path.write_text(f"""<mujoco model="{name}">{compiler}
  <worldbody>
    <body name="seat" pos="0 0 0.45">
      <geom name="noviz_collision_seat_0" type="cylinder" size="0.05 0.22" euler="{turn} 0 0" density="300"/>
      <site name="seat-leg,0,180,conn_site1" pos="0 -0.2 -0.05" size="0.01"/>
      <site name="seat-leg,0,180,conn_site2" pos="0 0.2 -0.05" size="0.01"/>
    </body>{legs}
  </worldbody>
</mujoco>
""")
  return path


def post_over_shim(directory, name="post_shim"):
  """A base board carrying a 2 mm shim and a post whose site leaves a 3 mm gap to the base.

  The post stands over the shim, so sliding it the 3 mm down to the base would push it
  2 mm into the shim (a third part).
  """
  path = pathlib.Path(directory) / f"{name}.xml"
  path.parent.mkdir(parents=True, exist_ok=True)
  path.write_text(f"""<mujoco model="{name}">
  <worldbody>
    <body name="base" pos="0 0 0.02">
      <geom name="noviz_collision_base_0" type="box" size="0.2 0.2 0.02" density="500"/>
      <site name="base-post,conn_site1" pos="0 0 0.02" size="0.01"/>
      <site name="base-shim,conn_site2" pos="0 0 0.02" size="0.01"/>
    </body>
    <body name="shim" pos="0 0 0.041">
      <geom name="noviz_collision_shim_0" type="box" size="0.05 0.05 0.001" density="500"/>
      <site name="shim-base,conn_site1" pos="0 0 -0.001" size="0.01"/>
    </body>
    <body name="post" pos="0 0 0.143">
      <geom name="noviz_collision_post_0" type="box" size="0.02 0.02 0.1" density="500"/>
      <site name="post-base,conn_site1" pos="0 0 -0.103" size="0.01"/>
    </body>
  </worldbody>
</mujoco>
""")
  return path


def frame_facing_back(directory, name="frame_back"):
  """A base board and a frame standing on it through two sites of one type, twist 0 only.

  The frame's sites face -y while the base's face +y, so the frame must turn a half
  turn about z to mate; the file writes it unturned, as one of the original's chairs
  does. Its site at +x then belongs on the base's site at -x: the pairs closest in the
  file (+x with +x) cannot both hold.
  """
  path = pathlib.Path(directory) / f"{name}.xml"
  path.parent.mkdir(parents=True, exist_ok=True)
  sites = {"base": "", "frame": ""}
  for k, x in enumerate((-0.15, 0.15)):
    sites["base"] += (f'\n      <site name="base-frame,0,conn_site{k}" pos="{x} 0 0.02" '
                      'size="0.01"/>')
    sites["frame"] += (f'\n      <site name="frame-base,0,conn_site{k}" pos="{x} 0 -0.1" '
                       'quat="0 0 0 1" size="0.01"/>')
  path.write_text(f"""<mujoco model="{name}">
  <worldbody>
    <body name="base" pos="0 0 0.02">
      <geom name="noviz_collision_base_0" type="box" size="0.3 0.2 0.02" density="500"/>{sites["base"]}
    </body>
    <body name="frame" pos="0.02 0.03 0.16">
      <geom name="noviz_collision_frame_0" type="box" size="0.2 0.01 0.1" density="500"/>{sites["frame"]}
    </body>
  </worldbody>
</mujoco>
""")
  return path


def _box_body(name, pos, size, sites):
  """A body with one collision box (density 500) and sites given as (name, pos, quat)."""
  xml = "".join(f'\n      <site name="{n}" pos="{p}" quat="{q}" size="0.01"/>' for n, p, q in sites)
  return f"""
    <body name="{name}" pos="{pos}">
      <geom name="noviz_collision_{name}_0" type="box" size="{size}" density="500"/>{xml}
    </body>"""


def _write(directory, name, bodies):
  path = pathlib.Path(directory) / f"{name}.xml"
  path.parent.mkdir(parents=True, exist_ok=True)
  path.write_text(f'<mujoco model="{name}">\n  <worldbody>{"".join(bodies)}\n  </worldbody>\n</mujoco>\n')
  return path


def cabinet_with_back(directory, name="cabinet_back"):
  """Two sides, two shelves and a back panel that overlaps each side by 2 mm, as in one of
  the original's bookcases (its back sits in the sides' grooves).

  The back's sites face +y (out of the panel), and it sits 10 mm in from the sides'
  back edges: it clears the sides by sliding 13 mm back. It mates both sides, and
  the right side is placed through the back (the left side's first site), so the
  right side hangs beyond the back in the solved tree while the shelves also hold it.
  """
  left, right = "0.7071068 0 -0.7071068 0", "0.7071068 0 0.7071068 0"   # up -x, up +x
  back_up = "0.7071068 -0.7071068 0 0"                                    # up +y
  bodies = []
  for s, (x, quat, inner) in enumerate(((-0.4, left, 0.01), (0.4, right, -0.01))):
    sites = [(f"{s}-3,0,180,conn_site{s}", f"{inner} 0.14 0", back_up)]
    sites += [(f"{s}-2,0,180,conn_site{k}", f"{inner} -0.01 {z - 0.4}", quat)
              for k, z in enumerate((0.1, 0.7))]
    bodies.append(_box_body(f"side{s}", f"{x} 0 0.4", "0.01 0.15 0.4", sites))
  for k, z in enumerate((0.1, 0.7)):
    bodies.append(_box_body(f"shelf{k}", f"0 -0.01 {z}", "0.39 0.14 0.01", [
        (f"2-0,0,180,conn_site{2 * k}", "-0.39 0 0", left),
        (f"2-1,0,180,conn_site{2 * k + 1}", "0.39 0 0", right)]))
  bodies.append(_box_body("back", "0 0.14 0.4", "0.392 0.003 0.38", [
      (f"3-{s},0,180,conn_site{s}", f"{x} 0 0", back_up) for s, x in enumerate((-0.39, 0.39))]))
  return _write(directory, name, bodies)


def box_with_wide_front(directory, overlap, name="box_front"):
  """A base board with two side walls and a front panel standing on it, the front's
  collision box `overlap` metres too wide at each end (into both walls), as some of
  the original's own collision boxes are. Sliding along its mate (up) cannot clear it.
  """
  up = "1 0 0 0"
  bodies = [_box_body("base", "0 0 0.01", "0.22 0.15 0.01", [
      ("base-wall,0,180,conn_site1", "-0.21 0 0.01", up),
      ("base-wall,0,180,conn_site2", "0.21 0 0.01", up),
      ("base-front,0,conn_site3", "0 -0.14 0.01", up)])]
  for i, x in enumerate((-0.21, 0.21)):
    bodies.append(_box_body(f"wall{i}", f"{x} 0 0.07", "0.01 0.15 0.05", [
        (f"wall-base,0,180,conn_site{i}", "0 0 -0.05", up)]))
  bodies.append(_box_body("front", "0 -0.14 0.07", f"{0.2 + overlap:.6g} 0.01 0.05", [
      ("front-base,0,conn_site1", "0 0 -0.05", up)]))
  return _write(directory, name, bodies)


def corner_shelf(directory, name="corner_shelf"):
  """A corner shelf: a side wall, a back wall against its face, and two boards each
  touching both walls, so that every part but the side touches two perpendicular faces."""
  west, north = "0.7071068 0 -0.7071068 0", "0.7071068 -0.7071068 0 0"   # up -x, up +y
  bodies = [_box_body("side", "-0.108 0.008 0.25", "0.008 0.108 0.25", [
      ("side-back,0,180,conn_site0", "0.008 0.092 0", west)] + [
      (f"side-shelf,0,180,conn_site{k}", f"0.008 -0.008 {z - 0.25:.3f}", west)
      for k, z in enumerate((0.15, 0.35))])]
  bodies.append(_box_body("back", "0 0.108 0.25", "0.1 0.008 0.25", [
      ("back-side,0,180,conn_site0", "-0.1 0 0", west)] + [
      (f"back-shelf,0,180,conn_site{k}", f"0 -0.008 {z - 0.25:.3f}", north)
      for k, z in enumerate((0.15, 0.35))]))
  for k, z in enumerate((0.15, 0.35)):
    bodies.append(_box_body(f"shelf{k}", f"0 0 {z}", "0.1 0.1 0.008", [
        (f"shelf-side,0,180,conn_site{k}", "-0.1 0 0", west),
        (f"shelf-back,0,180,conn_site{k}", "0 0.1 0", north)]))
  return _write(directory, name, bodies)


def wall_shelf(directory, name="wall_shelf"):
  """A wall-mounted unit: one 27 x 18 mm column 0.9 m tall with three open boxes hung on
  one side of it (as a column of a shelving system carries its boxes). Upright, its
  centre of mass lies beyond the column's footprint, so it cannot stand."""
  side = "0.7071068 0 0.7071068 0"   # up +x: a box hangs on the column's face
  bodies = [_box_body("column", "0 0 0.45", "0.0135 0.009 0.45", [
      (f"col-box{k},0,conn_site{k}", f"0 -0.009 {z - 0.45:.3f}", side)
      for k, z in enumerate((0.2, 0.45, 0.7))])]
  for k, z in enumerate((0.2, 0.45, 0.7)):
    bodies.append(f"""
    <body name="box{k}" pos="0 -0.049 {z}">
      <geom name="noviz_collision_box{k}_top" type="box" pos="0 0 0.057" size="0.06 0.04 0.003" density="500"/>
      <geom name="noviz_collision_box{k}_bottom" type="box" pos="0 0 -0.057" size="0.06 0.04 0.003" density="500"/>
      <geom name="noviz_collision_box{k}_back" type="box" pos="0 0.037 0" size="0.06 0.003 0.054" density="500"/>
      <site name="box{k}-col,0,conn_site{k}" pos="0 0.04 0" quat="{side}" size="0.01"/>
    </body>""")
  return _write(directory, name, bodies)



def _quat_mul(a, b):
  w1, x1, y1, z1 = a
  w2, x2, y2, z2 = b
  return (w1 * w2 - x1 * x2 - y1 * y2 - z1 * z2, w1 * x2 + x1 * w2 + y1 * z2 - z1 * y2,
          w1 * y2 - x1 * z2 + y1 * w2 + z1 * x2, w1 * z2 + x1 * y2 - y1 * x2 + z1 * w2)


def misnamed_chair(directory, name="chair_misnamed", short_back=0.0):
  """A chair laid out assembled whose names contradict the layout, as in one of the
  original's chairs: each side rail names 'side-back' the site at its front end, where it
  meets the front, and 'side-front' the one at its back end; and the back meets the rails
  turned 180 degrees about the up axis where its names allow only 0. Each rail has a stub
  leg under its front end, so a reversed rail is told apart. `short_back` (m) lifts the
  back panel's lower edge off the floor."""
  s = np.sqrt(0.5)
  up_back = (s, -s, 0.0, 0.0)                                # up +y
  up_front = (s, s, 0.0, 0.0)                                # up -y
  turned = _quat_mul(up_front, (0.0, 0.0, 0.0, 1.0))         # the same up, forward turned 180
  q = lambda quat: " ".join(f"{v:.7f}" for v in quat)
  bodies = [_box_body("front", "0 0 0.2", "0.2 0.01 0.2", [
      (f"front-side,0,conn_site{k}", f"{x} 0.01 0.1", q(up_back)) for k, x in enumerate((-0.19, 0.19))])]
  half = 0.3 - short_back / 2
  bodies.append(_box_body("back", "0 0.4 0.3", "0.2 0.01 0.3", [
      (f"back-side,0,conn_site{k}", f"{x} -0.01 0", q(up_front)) for k, x in enumerate((-0.19, 0.19))]).replace(
          'size="0.2 0.01 0.3"', f'pos="0 0 {0.3 - half:.4f}" size="0.2 0.01 {half:.4f}"'))
  for k, x in enumerate((-0.19, 0.19)):
    bodies.append(f"""
    <body name="rail{k}" pos="{x} 0.2 0.3">
      <geom name="noviz_collision_rail{k}_0" type="box" size="0.01 0.19 0.03" density="500"/>
      <geom name="noviz_collision_rail{k}_stub" type="box" pos="0 -0.15 -0.06" size="0.01 0.02 0.03" density="500"/>
      <site name="side-back,0,conn_site{k}" pos="0 -0.19 0" quat="{q(up_back)}" size="0.01"/>
      <site name="side-front,0,conn_site{k + 2}" pos="0 0.19 0" quat="{q(turned)}" size="0.01"/>
    </body>""")
  return _write(directory, name, bodies)


def _q(quat):
  return " ".join(f"{v:.9f}" for v in quat)


def post_in_socket(directory, name="post_socket"):
  """A base block with a square socket and a post that fills it exactly, touching all
  four walls (as a bench's leg sits between its top and its frame): the post can leave
  only by sliding up along the walls it touches, with no air around it."""
  walls = "".join(
      f'\n      <geom name="noviz_collision_base_{k}" type="box" pos="{x} {y} 0.03" '
      f'size="{sx} {sy} 0.03" density="500"/>'
      for k, (x, y, sx, sy) in enumerate(((-0.035, 0, 0.015, 0.05), (0.035, 0, 0.015, 0.05),
                                          (0, -0.035, 0.02, 0.015), (0, 0.035, 0.02, 0.015))))
  bodies = [f"""
    <body name="base" pos="0 0 0.02">
      <geom name="noviz_collision_base_floor" type="box" size="0.1 0.1 0.02" density="500"/>{walls}
      <site name="base-post,0,90,180,270,conn_site0" pos="0 0 0.02" size="0.01"/>
    </body>""", _box_body("post", "0 0 0.14", "0.02 0.02 0.1", [
        ("post-base,0,90,180,270,conn_site0", "0 0 -0.1", "1 0 0 0")])]
  return _write(directory, name, bodies)


def stool_with_sleeves(directory, name="stool_sleeves", tilt_deg=20.0):
  """A stool whose four legs splay out `tilt_deg` degrees, each seated in a sleeve under the
  seat with 2 mm of air round it: a leg leaves only along its own axis (the up axis of its
  connector, neither a coordinate axis nor a diagonal between two)."""
  t = np.radians(tilt_deg)
  leg_half, width, air, wall, sleeve = 0.15, 0.015, 0.002, 0.005, 0.04
  seat_z = 0.5
  geoms, sites, legs = [], [], []
  for k in range(4):
    yaw = np.radians(90.0 * k)
    turn = _quat_mul((np.cos(yaw / 2), 0, 0, np.sin(yaw / 2)), (np.cos(t / 2), np.sin(t / 2), 0, 0))
    rot = _rotation(turn)
    # The leg's top end, 1 mm under the seat's underside at its highest corner.
    top = np.array([-0.12 * np.sin(yaw), 0.12 * np.cos(yaw), 0.0])
    top[2] = seat_z - 0.01 - width * np.sin(t) - 0.001
    axis = rot[:, 2]
    centre = top - leg_half * axis
    down = _quat_mul(turn, (0, 1, 0, 0))   # the connector's up points down the leg
    sites.append((f"seat-leg,0,conn_site{k}", top - [0, 0, seat_z], down))
    for j, (dx, dy, sx, sy) in enumerate(((-1, 0, wall, width + air + 2 * wall),
                                          (1, 0, wall, width + air + 2 * wall),
                                          (0, -1, width + air, wall), (0, 1, width + air, wall))):
      off = (width + air + wall) * np.array([dx, dy, 0.0])
      pos = top - [0, 0, seat_z] - sleeve * axis + rot @ off
      geoms.append(f'\n      <geom name="noviz_collision_seat_{k}_{j}" type="box" '
                   f'pos="{pos[0]:.9f} {pos[1]:.9f} {pos[2]:.9f}" quat="{_q(turn)}" '
                   f'size="{sx} {sy} {sleeve}" density="500"/>')
    legs.append(f"""
    <body name="leg{k}" pos="{centre[0]:.9f} {centre[1]:.9f} {centre[2]:.9f}" quat="{_q(turn)}">
      <geom name="noviz_collision_leg{k}_0" type="box" size="{width} {width} {leg_half}" density="500"/>
      <site name="leg-seat,0,conn_site{k}" pos="0 0 {leg_half}" quat="0 1 0 0" size="0.01"/>
    </body>""")
  site_xml = "".join(f'\n      <site name="{n}" pos="{p[0]:.9f} {p[1]:.9f} {p[2]:.9f}" '
                     f'quat="{_q(q)}" size="0.01"/>' for n, p, q in sites)
  bodies = [f"""
    <body name="seat" pos="0 0 {seat_z}">
      <geom name="noviz_collision_seat_board" type="box" pos="0 0 -0.005" size="0.2 0.2 0.005" density="500"/>{"".join(geoms)}{site_xml}
    </body>"""] + legs
  return _write(directory, name, bodies)


def _rotation(quat):
  w, x, y, z = quat
  return np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
                   [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
                   [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)]])


def box_with_wide_mesh_front(directory, overlap, name="box_mesh_front"):
  """box_with_wide_front whose front panel collides through its own (convex) mesh, seen
  too, `overlap` metres too wide at each end: a mesh part overlapping two others."""
  path = box_with_wide_front(directory, overlap, name)
  folder = pathlib.Path(directory) / name
  folder.mkdir(parents=True, exist_ok=True)
  trimesh.creation.box(extents=(0.4 + 2 * overlap, 0.02, 0.1)).export(folder / "front.stl")
  text = path.read_text().replace(
      '<geom name="noviz_collision_front_0" type="box" size="{:.6g} 0.01 0.05" density="500"/>'
      .format(0.2 + overlap),
      '<geom name="front_mesh" type="mesh" mesh="front" density="500"/>')
  text = text.replace("<worldbody>", f'<asset>\n    <mesh name="front" file="{name}/front.stl"/>\n'
                      "  </asset>\n  <worldbody>", 1)
  path.write_text(text)
  return path


def bracket_with_boards(directory, name="bracket_boards"):
  """A 4 cm bracket, a few grams, holding a long heavy board (2 kg) and a short one by their
  ends, as some of the original's desks hang their boards from a small connecting block.
  The bracket has the most connectors, so the assembly is built onto it."""
  arms = {"long": (1, "0.7071068 0 0.7071068 0", 0.25),
          "short": (-1, "0.7071068 0 -0.7071068 0", 0.1)}
  sites = [(f"bracket-{k},0,conn_site{i}", f"{0.02 * dx} 0 -0.01", q)
           for i, (k, (dx, q, _)) in enumerate(arms.items())]
  bodies = [_box_body("bracket", "0 0 0.02", "0.02 0.02 0.02", sites).replace(
      'density="500"', 'density="100"')]
  for i, (k, (dx, q, half)) in enumerate(arms.items()):
    bodies.append(_box_body(f"board_{k}", f"{(0.02 + half) * dx} 0 0.01", f"{half} 0.15 0.01", [
        (f"{k}-bracket,0,conn_site{i}", f"{-half * dx} 0 0", q)]).replace(
            'density="500"', 'density="700"'))
  return _write(directory, name, bodies)
