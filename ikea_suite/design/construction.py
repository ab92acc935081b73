"""What each part is made of: the one table of materials and constructions behind every mass.

A part's visual finish (`materials.MATERIALS`: white laminate, birch, metal)
says how it looks; its construction says what is inside and so what it
weighs. The family code assigns a construction where it knows what the part is
(a Lack-style top is honeycomb board, a carcass side is particleboard, a back
panel is 3 mm hardboard, a shelving post is a hollow steel tube); nothing is
guessed from the finish, except the species of a part the family declares to
be solid wood (`solid_wood`).

Kinds of construction (mass properties in `mass_properties`):
  solid      the geom's whole volume at `density`.
  plate      a sheet `thickness` thick, centred in the geom across its two
             largest extents: a hardboard back or drawer bottom modelled as a
             thicker collision box, a steel base plate, a plastic box wall.
  honeycomb  board-on-frame: two face sheets (`face_thickness`, `density`), an
             edge frame `frame_width` wide (`frame_density`) round the panel
             and a paper honeycomb core (`core_density`) in between.
  tube       a hollow section with walls `thickness` thick along the geom's
             long axis: a round tube for a cylinder, a rectangular one for a
             box; `core_density` fills the inside (paper in a hollow leg).
  tray       sheet folded into a tray: a top sheet `thickness` thick plus lips
             down the four edges, open underneath (a steel shelf).

Densities are docs/physics.md's typical values (its range in the comment).
"""

import dataclasses

SOLID, PLATE, HONEYCOMB, TUBE, TRAY = "solid", "plate", "honeycomb", "tube", "tray"
KINDS = (SOLID, PLATE, HONEYCOMB, TUBE, TRAY)

# Material densities, kg/m^3 (docs/physics.md, "Materials and masses").
PINE_DENSITY = 500.0            # docs/physics.md: pine 420-550
BIRCH_DENSITY = 650.0           # docs/physics.md: birch 600-700, birch plywood 550-700
OAK_DENSITY = 700.0             # docs/physics.md: oak 650-750
PARTICLEBOARD_DENSITY = 650.0   # docs/physics.md: particleboard 600-750
FIBREBOARD_DENSITY = 750.0      # docs/physics.md: MDF / fibreboard 650-800
HARDBOARD_DENSITY = 800.0       # docs/physics.md: fibreboard 650-800; hardboard is the dense end
STEEL_DENSITY = 7850.0          # docs/physics.md: steel 7850
PLASTIC_DENSITY = 950.0         # docs/physics.md: ABS / PP 900-1100; PP boxes sit near 900
# Paper honeycomb core. No measured figure at hand: docs/physics.md gives the whole
# board (150-300 kg/m^3 effective; a 55 x 55 x 5 cm top 2-3 kg), and the faces
# and frame below already make 2.6 kg of such a top, so the core is what is left,
# a few tenths of a kilogram (0.29 kg at this density).
PAPER_CORE_DENSITY = 25.0


@dataclasses.dataclass(frozen=True)
class Construction:
  """How a part (or one geom of it) is built; lengths in metres, densities in kg/m^3."""
  name: str
  kind: str
  density: float                 # the material (faces, walls, sheet or solid)
  thickness: float = 0.0         # plate, tube wall, tray sheet; honeycomb face sheet
  frame_width: float = 0.0       # honeycomb edge frame
  frame_density: float = 0.0     # honeycomb edge frame
  core_density: float = 0.0      # honeycomb core; paper inside a hollow leg
  note: str = ""

  def __post_init__(self):
    if self.kind not in KINDS:
      raise ValueError(f"construction {self.name!r}: kind {self.kind!r} is not one of {KINDS}")


PINE = Construction("solid pine", SOLID, PINE_DENSITY,
                    note="chairs, stools, benches, bed slats, painted and stained solid wood")
BIRCH = Construction("solid birch", SOLID, BIRCH_DENSITY, note="birch chairs, stools, plywood")
OAK = Construction("solid oak", SOLID, OAK_DENSITY, note="oak chairs, benches, legs")
PARTICLEBOARD = Construction("particleboard", SOLID, PARTICLEBOARD_DENSITY,
                             note="carcass sides, shelves, doors, desk and table tops")
MDF = Construction("MDF", SOLID, FIBREBOARD_DENSITY, note="painted fibreboard boxes")
# docs/physics.md: "back panels are often 3 mm hardboard"; drawer bottoms are the same sheet.
HARDBOARD = Construction("3 mm hardboard", PLATE, HARDBOARD_DENSITY, thickness=0.003,
                         note="carcass back panels and drawer bottoms")
# Board-on-frame as in the Lack range: fibreboard faces on a particleboard frame
# round a paper honeycomb. 3 mm faces and a 20 mm frame give a 55 x 55 x 5 cm top
# of 2.9 kg, inside docs/physics.md's 2-3 kg.
HONEYCOMB_BOARD = Construction("honeycomb board", HONEYCOMB, FIBREBOARD_DENSITY,
                               thickness=0.003, frame_width=0.02,
                               frame_density=PARTICLEBOARD_DENSITY,
                               core_density=PAPER_CORE_DENSITY,
                               note="Lack-style table tops, TV bench tops")
# A Lack-style leg is a fibreboard shell round a paper core with a screw block
# at the top: four 3 mm walls (0.19 kg for a 5 x 5 x 40 cm leg). With the honeycomb
# top this makes the 55 x 55 cm side table 3.6 kg; the retailer lists the real one at 8 lb, 3.6 kg
# (invertedkeyboard.com, "IKEA LACK Side Table Review", 2013).
HOLLOW_FIBREBOARD_LEG = Construction("hollow fibreboard leg", TUBE, FIBREBOARD_DENSITY,
                                     thickness=0.003, core_density=PAPER_CORE_DENSITY,
                                     note="Lack-style square legs")
# docs/physics.md: furniture frames are hollow tube, wall 1-2 mm.
STEEL_TUBE = Construction("hollow steel tube", TUBE, STEEL_DENSITY, thickness=0.0015,
                          note="metal table and desk legs, posts, shelving uprights and rungs")
# Sheet-steel shelves of post shelving: 0.8 mm sheet folded into a tray (docs/physics.md:
# frames are "hollow tube (wall 1-2 mm) or sheet"; shelf sheet is thinner than tube wall).
STEEL_SHEET = Construction("sheet steel tray", TRAY, STEEL_DENSITY, thickness=0.0008,
                           note="shelves of steel shelving")
# A pedestal's foot is a steel plate heavy enough to keep the table upright:
# 5 mm over the foot's disc (a 45 cm foot: 6.2 kg).
STEEL_PLATE = Construction("5 mm steel plate", PLATE, STEEL_DENSITY, thickness=0.005,
                           note="feet of pedestal tables and stools")
# Injection-moulded PP box walls are 2-3 mm.
PLASTIC_SHEET = Construction("2.5 mm polypropylene", PLATE, PLASTIC_DENSITY, thickness=0.0025,
                             note="plastic storage boxes")

def solid(density, source):
  """A solid construction of a given density (kg/m^3), e.g. one that keeps an imported
  model's own masses; `source` says where the density comes from."""
  return Construction(f"solid at {density:g} kg/m^3", SOLID, float(density), note=source)


ALL = (PINE, BIRCH, OAK, PARTICLEBOARD, MDF, HARDBOARD, HONEYCOMB_BOARD, HOLLOW_FIBREBOARD_LEG,
       STEEL_TUBE, STEEL_SHEET, STEEL_PLATE, PLASTIC_SHEET)
BY_NAME = {c.name: c for c in ALL}
# Constructions that make sense for an arbitrary solid shape (an imported mesh or
# primitive); hollow and layered ones need the shape they were modelled for.
SOLIDS = {c.name: c for c in ALL if c.kind == SOLID}

# Finish -> species, for parts a family declares solid wood: birch-coloured wood is
# birch, medium (oak-coloured) wood is oak, and everything else (light, stained dark,
# painted white or black) is pine, the usual wood of painted and stained flat-pack.
_SPECIES = {"birch": BIRCH, "wood_medium": OAK}


def solid_wood(finish):
  """The solid-wood construction of a part the family makes of solid wood, by its finish."""
  return _SPECIES.get(finish, PINE)


def leg(finish):
  """A chair, table or desk leg: steel tube when metal, else solid wood of its finish."""
  return STEEL_TUBE if finish == "metal" else solid_wood(finish)
