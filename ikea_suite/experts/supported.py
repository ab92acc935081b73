"""Which (furniture, robot) pairs the scripted experts assemble, as measured.

Filled from benchmarks/expert_sweep.py on seeds the experts were never tuned
on (--seed-start 1000, 10 seeds per model): a pair is listed when at least
8 of 10 episodes completed the furniture. The scale is the one the robot
assembles that furniture at (its WORK_SCALE). The sweep tables behind these
lists are in the README ("Scripted experts").
"""

# robot -> {furniture: scale}
SUPPORTED = {
    "cursor": None,   # the Cursor oracle: every catalog model at full size
    # Fresh seeds 1000-1009 after the 2026-11-25 controller changes (README, "Expert sweep").
    "sawyer": {"stool_round_bar_birch": 0.5,      # 9/10
               "stool_round_frosta": 0.5,         # 8/10
               "stool_round_low_white": 0.5,      # 8/10
               "stool_square_pine": 0.5,          # 9/10
               "table_four_leg_side_oak": 0.5,    # 8/10
               "table_four_leg_w75_black": 0.5},  # 9/10
    "panda": {"table_four_leg_side_oak": 0.5},    # 8/10
    "baxter": {},
    "jaco": {},
}
