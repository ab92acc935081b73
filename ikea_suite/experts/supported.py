"""Which (furniture, robot) pairs the scripted experts assemble, as measured.

Filled from benchmarks/expert_sweep.py on seeds the experts were never tuned
on: a pair is listed when at least 80% of its episodes completed the
furniture, over 20 seeds (6000-6019: --seed-start 6000 and 6010, --seeds 10)
for the Sawyer and Panda and 10 (6000-6009) for the Baxter and Jaco, with the
code of 2026-11-25, fifth session (fingertips kept above the floor;
the Jaco's hold; per-model work scales below WORK_SCALE, none of which is
listed). The scale is the one the robot assembles that furniture at (its
WORK_SCALE). The sweep tables behind these lists are in the README ("Expert
sweep"). Baxter's earlier entries (frosta and w75_black, 8/10 on 5000-5009)
fell to 5/10 and 1/10 on these seeds; the code before this session scored
the same seeds alike (w75_black 0/10), so its seed-to-seed spread, not a
change, took them off.
"""

# robot -> {furniture: scale}
SUPPORTED = {
    "cursor": None,   # the Cursor oracle: every catalog model at full size
    "sawyer": {"stool_round_bar_birch": 0.5,      # 19/20
               "stool_round_four_leg": 0.5,       # 18/20
               "stool_round_frosta": 0.5,         # 19/20
               "stool_round_low_white": 0.5,      # 20/20
               "stool_square_dark_low": 0.5,      # 16/20
               "table_four_leg_side_oak": 0.5,    # 20/20
               "table_four_leg_w120_white": 0.5,  # 16/20
               "table_four_leg_w75_black": 0.5},  # 19/20
    "panda": {"stool_round_frosta": 0.5,          # 19/20
              "stool_round_low_white": 0.5,       # 17/20
              "table_four_leg_side_oak": 0.5},    # 18/20 (stool_square_pine: 8/10, then 10/20)
    "baxter": {},   # best on 6000-6009: stool_round_low_white 6/10
    "jaco": {},     # best on 6000-6009: stool_round_bar_birch 3/10
}
