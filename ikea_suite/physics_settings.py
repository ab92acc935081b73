"""The one physics configuration of ikea_suite, used by every tool that simulates.

The environment (`configure_arena`), the validator, the sequencer and the
gallery (`configure_model` on a plain MjModel) and the model writer (`OPTION`,
`WELD_SOLREF`, `WELD_SOLIMP` written into each file) all read these values, so
a model behaves the same wherever it is simulated. Reasons follow MuJoCo's
modelling guidance (mujoco.readthedocs.io, "Modeling" and "Computation") and
the calibration tests in tests/test_physics_settings.py.
"""

import numpy as np

TIMESTEP = 0.002   # s; 25 substeps per 20 Hz control step, fast enough for 2 cm parts at 1 m/s

OPTION = {
    "timestep": TIMESTEP,
    # Implicit in velocity for joint damping and actuator gains: stable with the
    # arms' stiff position servos, and MuJoCo's recommended default.
    "integrator": "implicitfast",
    # Elliptic cones model Coulomb friction exactly; impratio > 1 makes friction
    # stiffer than normal forces, which stops parts slowly slipping out of fingers.
    "cone": "elliptic",
    "impratio": 10,
    # No noslip pass: with impratio 10 a 3 s grasp slips < 1 mm (tests), and
    # noslip costs a second solver sweep on every step.
    "noslip_iterations": 0,
}

# MuJoCo's arena holds contacts and constraints. A random-action soak of all
# 645 furniture x robot pairs (benchmarks/soak.py) used at most 3.6 MB and
# 1,735 contacts; 32 MB leaves a ninefold margin (MuJoCo sizes it by model
# otherwise, and a pile of parts once overflowed that).
ARENA_MEMORY = "32M"

# Welds between connected parts. The time constant is twice the timestep, the
# stiffest MuJoCo integrates stably, and solimp near 1 makes the weld nearly
# hard (impedance 0.999 -> 0.9999 over 1 mm). The rotational residual is
# weighted 10 m per rad, so 1 mrad of bending costs as much as 1 cm of offset:
# a table hung from one leg otherwise swings 22 mm about that leg's weld.
# Measured (test_physics_settings, shaken 3 s in the air by one part): table 0.26 mm,
# chair 0.10 mm, bookcase 0.06 mm of deformation; limit 1 mm.
WELD_SOLREF = (2 * TIMESTEP, 1.0)
WELD_SOLIMP = (0.999, 0.9999, 0.001, 0.5, 2.0)
WELD_TORQUESCALE = 10.0

# The Cursor's grip: a weld from the world to the held part, 5 ms. An assembly
# held by one part must not swing when a part is pushed into it: with a
# 20 ms grip a bench on rigid welds tilted 30 degrees about its grip during an
# insertion (bench_slatted_oak), and 13 of 387 oracle episodes failed that way; at
# 5 ms all of them assemble.
CURSOR_GRIP_SOLREF = (0.005, 1.0)

# Contacts between parts and robot: MuJoCo's default time constant (20 ms) and
# impedance (0.9-0.95), stated here so every tool uses them (the floor: below).
# Stiffer contacts (5 ms, 0.95-0.99) sank a 52 kg dresser 0.11 mm into the
# floor instead of 0.44 mm, but overpowered the Cursor's soft grip weld: a
# 0.14 kg plastic box wall jammed 21 degrees off against the box bottom during
# insertion (box_open_kuggis), so the default stays.
CONTACT_SOLREF = (0.02, 1.0)
CONTACT_SOLIMP = (0.9, 0.95, 0.001, 0.5, 2.0)

# Round geoms (cylinders, capsules, spheres, ellipsoids) touch with condim 6, so
# their rolling and torsional friction (MuJoCo's default coefficients, 1e-4 m and
# 5e-3 m, unless a geom sets its own) act: with condim 3 a dropped round leg rolls
# on for ever (measured: 151 m over a 155 s Sawyer episode). Boxes cannot roll and
# keep condim 3, since six-dimensional contacts cost about a fifth more per step.
ROUND_GEOM_CONDIM = 6

# Finger pads touch with the impedance MuJoCo's documentation gives for hard
# contacts (0.95-0.99) instead of the default 0.9-0.95: soft friction lets a
# squeezed part creep, and at the default a 32 g leg held in 22 N fingers crept
# 12 mm out of the Sawyer's pads in 4.5 s of carrying and was dropped (stool_square_pine). A large solmix makes the pad's impedance win over the part's when MuJoCo
# mixes the two geoms' parameters.
# MuJoCo's stable hard constraint: time constant two timesteps, impedance 0.95-0.99
# (docs/physics.md); the pads' impedance, the grippers' finger coupling and the Jaco's fingers.
HARD_SOLREF = (2 * TIMESTEP, 1.0)
HARD_SOLIMP = (0.95, 0.99, 0.001, 0.5, 2.0)
PAD_SOLIMP = HARD_SOLIMP
PAD_SOLMIX = 1000.0

# Surfaces parts stand on (the floor, a work table's top) are hard too: MuJoCo's contact
# softness scales with the touching body's inverse mass, so at the default impedance a
# light board carrying a heavy carcass through welds sinks in. The original IKEA
# env's cabinet_akurum_0014 stands on three 1-1.6 g plinths under a 100 g carcass: they
# sank 0.8-3.2 mm and the 0.72 m cabinet leaned 1 degree (12.7 mm drift in 5 s); on a
# hard floor 1.7 mm. The catalog's heaviest dresser (45 kg) sinks
# 0.21 mm instead of 0.38. The time constant stays 20 ms: a 4 ms floor turned
# chair_balser_0115 past the 0.2 degree stand limit. The large solmix makes the
# surface's impedance win over a part's; pads (same solmix, same impedance) mix evenly.
SUPPORT_SOLIMP = HARD_SOLIMP
SUPPORT_SOLMIX = PAD_SOLMIX

# Convex collision tolerance (m) of a scene whose parts rest on a box (a work table's top)
# instead of the floor plane. A plane meets a part through MuJoCo's exact plane colliders;
# a box meets a cylinder through the general convex collider (GJK/EPA, with several
# contacts for a flat pair, MuJoCo's multiccd), which stops at its tolerance (default
# 1e-6). At the default the contacts of a round leg lying on its side came 6-58 um to one
# side of the line under its axis, and that lever alone rolled the leg over, 14-116
# degrees in 2 s (work table, scale 0.5); at 1e-8 the leg lies still, but a pedestal
# stool tipped onto its foot's rim still turned 1.6 degrees in 2 s; from 1e-9 on both
# lie as on the floor, and 1e-10 leaves a decade of margin (no step-time cost measured:
# a Sawyer episode on the table ran 117-128 steps/s at 1e-6, 1e-8 and 1e-10 alike). The
# floor scene keeps the default: its parts touch only each other and the robot through
# this collider, and its episodes (scripts/episode_hashes.py) change with the tolerance.
BOX_SUPPORT_CCD_TOLERANCE = 1e-10
_PLANE = 0   # mjGEOM_PLANE: the floor of a model file
_ROUND_TYPES = (2, 3, 4, 5)   # mjGEOM_SPHERE, CAPSULE, ELLIPSOID, CYLINDER


def configure_arena(mjcf_root):
  """Writes the option block and arena size into the root MJCF of an environment."""
  mjcf_root.option.set_attributes(**OPTION)
  mjcf_root.size.memory = ARENA_MEMORY


def configure_box_support(mjcf_root):
  """Writes the convex collision tolerance of a scene whose parts rest on a box
  (BOX_SUPPORT_CCD_TOLERANCE) into its root MJCF; configure_arena leaves it as set."""
  mjcf_root.option.ccd_tolerance = BOX_SUPPORT_CCD_TOLERANCE


def configure_contacts(model, geom_ids=None):
  """Sets the contact parameters on compiled geoms: entities attached to an arena keep
  their own MJCF defaults, so this is applied to the compiled model instead."""
  ids = np.arange(model.ngeom) if geom_ids is None else np.asarray(geom_ids, dtype=int)
  model.geom_solref[ids] = CONTACT_SOLREF
  model.geom_solimp[ids] = CONTACT_SOLIMP
  round_ids = ids[np.isin(model.geom_type[ids], _ROUND_TYPES)
                  & (model.geom_condim[ids] == 3)]   # keep a geom's own choice (pads: 4)
  model.geom_condim[round_ids] = ROUND_GEOM_CONDIM


def configure_supports(model, geom_ids):
  """Sets the hard impedance of the surfaces parts stand on (SUPPORT_SOLIMP) on compiled
  geoms; call after configure_contacts, which resets every geom to the default."""
  ids = np.asarray(geom_ids, dtype=int)
  model.geom_solimp[ids] = SUPPORT_SOLIMP
  model.geom_solmix[ids] = SUPPORT_SOLMIX


def configure_pads(model, geom_ids, solref=CONTACT_SOLREF):
  """Sets the finger-pad contact impedance (PAD_SOLIMP) and `solref` on compiled pad geoms;
  call after configure_contacts, which resets every geom to the default."""
  ids = np.asarray(geom_ids, dtype=int)
  model.geom_solimp[ids] = PAD_SOLIMP
  model.geom_solref[ids] = solref
  model.geom_solmix[ids] = PAD_SOLMIX


def configure_model(model):
  """Applies the whole configuration to a plain mujoco.MjModel compiled from a file."""
  model.opt.timestep = TIMESTEP
  model.opt.integrator = {"euler": 0, "rk4": 1, "implicit": 2, "implicitfast": 3}[OPTION["integrator"].lower()]
  model.opt.cone = 1   # elliptic
  model.opt.impratio = OPTION["impratio"]
  model.opt.noslip_iterations = OPTION["noslip_iterations"]
  configure_contacts(model)
  configure_supports(model, np.flatnonzero(model.geom_type == _PLANE))
  welds = np.flatnonzero(model.eq_type == 1)   # mjEQ_WELD
  model.eq_solref[welds] = WELD_SOLREF
  model.eq_solimp[welds] = WELD_SOLIMP
  model.eq_data[welds, 10] = WELD_TORQUESCALE
