"""Which (furniture, robot) pairs the scripted experts assemble, as measured.

Filled from benchmarks/expert_sweep.py on seeds the experts were never tuned
on: a pair is listed when at least 80% of its episodes completed the
furniture, over 20 seeds (4000-4019: --seed-start 4000 and 4010, --seeds 10)
for the Sawyer and Panda and 10 (4000-4009) for the Baxter and Jaco, with the
code of 2026-11-25, third session. The scale is the one the robot assembles
that furniture at (its WORK_SCALE). The sweep tables behind these lists are
in the README ("Expert sweep").
"""

# robot -> {furniture: scale}
SUPPORTED = {
    "cursor": None,   # the Cursor oracle: every catalog model at full size
    "sawyer": {"stool_round_bar_birch": 0.5,      # 19/20
               "stool_round_four_leg": 0.5,       # 16/20
               "stool_round_frosta": 0.5,         # 18/20
               "stool_round_low_white": 0.5,      # 17/20
               "table_four_leg_side_oak": 0.5,    # 16/20
               "table_four_leg_w75_black": 0.5},  # 20/20
    "panda": {"stool_round_frosta": 0.5,          # 16/20
              "table_four_leg_side_oak": 0.5},    # 17/20
    "baxter": {},   # best: stool_round_bar_birch 6/10
    "jaco": {},     # best: 1/10
}
