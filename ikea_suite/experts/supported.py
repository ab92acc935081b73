"""Which (furniture, robot) pairs the scripted experts assemble, as measured.

Filled from benchmarks/expert_sweep.py on seeds the experts were never tuned
on: a pair is listed when at least 80% of its episodes completed the
furniture over 20 seeds, 11000-11019 (--seed-start 11000 and 11010, --seeds
10), with the code of 2026-11-26, eighth session: the floor's hard contact
impedance (physics_settings.SUPPORT_SOLIMP), the experts as in the seventh
session. A Baxter pair also needs both arms in at least 16 of its complete
episodes. The Jaco: no stool or table reaches 80%; its seven boxes do (below). The Panda's boxes and bench, whose
walls, ends and stretcher stand in the panel rack (tasks/panel_placement.py),
were measured with the code of the ninth session on 40 other fresh seeds each:
the boxes on 15000-15019 and 16000-16019, the benches, trestle desks and tables
on 17000-17019 and 18000-18019 (--seeds 20), and are listed at 80% of those 40;
its stools and tables, and the boxes, run exactly as before with the final code
(episodes replayed step for step). The tables are in the README ("Expert
sweep"). The scale is the one the robot assembles that furniture at (its
WORK_SCALE; per-model work scales below it, none of which is listed).
"""

# robot -> {furniture: scale}
SUPPORTED = {
    "cursor": None,   # the Cursor oracle: every catalog model at full size
    "sawyer": {"stool_round_bar_birch": 0.5,      # 18/20
               "stool_round_four_leg": 0.5,       # 20/20
               "stool_round_frosta": 0.5,         # 20/20
               "stool_round_low_white": 0.5,      # 20/20
               "stool_square_dark_low": 0.5,      # 17/20
               "table_four_leg_kids_white": 0.5,  # 18/20
               "table_four_leg_side_oak": 0.5,    # 19/20
               "table_four_leg_w120_white": 0.5,  # 17/20
               "table_four_leg_w75_black": 0.5},  # 20/20 (the Lack, the bar table, pine,
                                                  # white_tall 15/20; w90 14/20)
    "panda": {"bench_plank_white_short": 0.5,     # 36/40 (17000-17019, 18000-18019)
              "box_divided_birch": 0.5,           # 37/40 (15000-15019, 16000-16019)
              "box_open_kuggis": 0.5,             # 40/40
              "box_open_large_birch": 0.5,        # 37/40
              "box_open_shoe_dark": 0.5,          # 40/40
              "box_open_small_white": 0.5,        # 38/40
              "box_open_tall_black": 0.5,         # 37/40
              "stool_round_four_leg": 0.5,        # 17/20
              "stool_round_frosta": 0.5,          # 17/20
              "stool_round_low_white": 0.5,       # 17/20
              "table_four_leg_kids_white": 0.5,   # 17/20
              "table_four_leg_lack": 0.5,         # 17/20
              "table_four_leg_side_oak": 0.5,     # 18/20
              "table_four_leg_w75_black": 0.5,    # 17/20
              "table_four_leg_w90_birch": 0.5},   # 17/20 (stool_round_bar_birch: 15/20;
                                                  # box_divided_white_long 31/40,
                                                  # bench_plank_pine 30/40)
    "baxter": {"stool_round_bar_birch": 0.5,      # 18/20, both arms in all 18
               "stool_round_four_leg": 0.5,       # 16/20, both arms in all 16
               "stool_round_frosta": 0.5,         # 18/20, both arms in 17
               "stool_square_pine": 0.5},         # 16/20, both arms in all 16
               # low_white and dark_low: 16/20, both arms in 15; side_oak 14/20
    # The Jaco's boxes: fresh seeds 21000-21019, the tenth session's code (the carry
    # lowered to what the arm reaches; its stools and tables: best on 11000-11019
    # stool_round_low_white 8/20, frosta 6/20).
    "jaco": {"box_divided_birch": 0.5,            # 20/20
             "box_divided_white_long": 0.5,       # 20/20
             "box_open_kuggis": 0.5,              # 19/20
             "box_open_large_birch": 0.5,         # 20/20
             "box_open_shoe_dark": 0.5,           # 20/20
             "box_open_small_white": 0.5,         # 20/20
             "box_open_tall_black": 0.5},         # 20/20
}
