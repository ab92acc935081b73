"""Which (furniture, robot) pairs the scripted experts assemble, as measured.

Filled from benchmarks/expert_sweep.py on seeds the experts were never tuned
on: a pair is listed when at least 80% of its episodes completed the
furniture, over 20 seeds (5000-5019: --seed-start 5000 and 5010, --seeds 10)
for the Sawyer and Panda and 10 (5000-5009) for the Baxter and Jaco, with the
code of 2026-11-25, fourth session (the arm unwinds home between parts). The scale is the one the robot assembles
that furniture at (its WORK_SCALE). The sweep tables behind these lists are
in the README ("Expert sweep").
"""

# robot -> {furniture: scale}
SUPPORTED = {
    "cursor": None,   # the Cursor oracle: every catalog model at full size
    "sawyer": {"stool_round_bar_birch": 0.5,      # 17/20
               "stool_round_four_leg": 0.5,       # 20/20
               "stool_round_frosta": 0.5,         # 19/20
               "stool_round_low_white": 0.5,      # 20/20
               "stool_square_dark_low": 0.5,      # 16/20
               "table_four_leg_side_oak": 0.5,    # 19/20
               "table_four_leg_w75_black": 0.5},  # 18/20
    "panda": {"stool_round_frosta": 0.5,          # 17/20
              "stool_round_low_white": 0.5,       # 18/20
              "table_four_leg_side_oak": 0.5,     # 16/20
              "table_four_leg_w90_birch": 0.5},   # 16/20
    "baxter": {"stool_round_frosta": 0.5,         # 8/10 (both arms in 9 of 10)
               "table_four_leg_w75_black": 0.5},  # 8/10 (both arms in 10 of 10)
    "jaco": {},     # best on fresh seeds 6000-6009 (fifth session): stool_round_frosta 3/10
}
