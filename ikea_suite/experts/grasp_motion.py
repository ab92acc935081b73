"""How an arm's hand comes down onto a part, closes on it, and lowers what it holds:
speeds and gates of the scripted arm expert (single_arm), each measured where it
was set."""

# The open fingers go down to a part slowly: at full speed the hand swings sideways by
# up to 2.6 cm (Sawyer, 7 cm descent in 3 steps) and a finger lands on the part.
DESCEND_GAIN = 0.3
# A hand whose fingers curl below the tool centre closes only once it moves less than this
# per control step (m): 1 mm still let the Jaco's hand swing 1 cm while closing.
SETTLED_SPEED = 0.0005
# Such a hand (one finger against two) holds a lifted part with its fingers aimed this far
# (rad) short of their closed limit instead of past it; see arm_motion.hold_command.
HOLD_SHORT_OF_CLOSED = 0.05
# A panel held by its top edge (top_down_grasp.by_top_edge) hangs from the fingers: it goes
# down onto its mate at this fraction of the arm's top speed (at 25 mm a step it swung
# as the arm stopped), and the fingers close on it only within EDGE_GATE (m): 6 mm off,
# as for a leg, one finger pushed a 6 mm box wall over in its slot, the hand held it
# askew on its top edge, and it pivoted out of the grip during the carry.
HANGING_SPEED, EDGE_GATE = 0.3, 0.0015
# The open fingers pass 2 cm either side of a racked panel (Sawyer): the descent onto its
# top edge starts only within EDGE_REACH (m) of the point above it, and goes down at
# HANGING_SPEED. Started 2 cm off (the REACH gate) with the tool lagging its target, and
# at full speed, a fingertip landed on the edge and pushed the panel out of the rack
# (Sawyer, desk_trestle_w100_birch tuning seeds 4, 14, 17, 18).
EDGE_REACH = 0.006
