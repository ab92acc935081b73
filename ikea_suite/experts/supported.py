"""Which (furniture, robot) pairs the scripted experts assemble, as measured.

Filled from benchmarks/expert_sweep.py on seeds the experts were never tuned
on: a pair is listed when at least 80% of its episodes completed the
furniture over 20 seeds. The Sawyer and Panda: seeds 7000-7019 (--seed-start
7000 and 7010, --seeds 10) with the code of 2026-11-25, sixth session (fingers
that land clear, a held part with no mate left set back down). The Baxter:
seeds 10000-10019 with its parts placed 0.62-0.82 m from the torso and its
root 0.55 m out (2026-11-26, seventh session), its expert using both arms in
294 of the 300 episodes. The Jaco, 10 seeds (7000-7009): no model reaches
80%. The tables are in the README ("Expert sweep"). The scale is the one the
robot assembles that furniture at (its WORK_SCALE; per-model work scales
below it, none of which is listed).
"""

# robot -> {furniture: scale}
SUPPORTED = {
    "cursor": None,   # the Cursor oracle: every catalog model at full size
    "sawyer": {"stool_round_bar_birch": 0.5,      # 18/20
               "stool_round_four_leg": 0.5,       # 20/20
               "stool_round_frosta": 0.5,         # 20/20
               "stool_round_low_white": 0.5,      # 19/20
               "table_four_leg_bar_birch": 0.5,   # 16/20
               "table_four_leg_kids_white": 0.5,  # 17/20
               "table_four_leg_lack": 0.5,        # 17/20
               "table_four_leg_side_oak": 0.5,    # 16/20
               "table_four_leg_w120_white": 0.5,  # 17/20
               "table_four_leg_w75_black": 0.5,   # 19/20
               "table_four_leg_w90_birch": 0.5},  # 17/20 (stool_square_dark_low: 15/20)
    "panda": {"stool_round_bar_birch": 0.5,       # 17/20
              "stool_round_frosta": 0.5,          # 17/20
              "stool_round_low_white": 0.5,       # 17/20
              "table_four_leg_lack": 0.5,         # 16/20
              "table_four_leg_side_oak": 0.5,     # 17/20
              "table_four_leg_w75_black": 0.5},   # 17/20 (stool_square_dark_low: 14/20)
    "baxter": {"stool_round_bar_birch": 0.5,      # 17/20, both arms in 16
               "stool_round_four_leg": 0.5,       # 19/20, both arms in all 19
               "stool_round_frosta": 0.5,         # 20/20, both arms in 18
               "stool_round_low_white": 0.5,      # 20/20, both arms in 18
               "stool_square_dark_low": 0.5,      # 17/20, both arms in 16
               "table_four_leg_side_oak": 0.5},   # 16/20, both arms in all 16
    "jaco": {},     # best on 7000-7009: stool_round_frosta and low_white 4/10
}
