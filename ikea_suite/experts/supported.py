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
    # Fresh seeds 1000-1009 (README, "Expert sweep"): stool_round_frosta 9/10.
    "sawyer": {"stool_round_frosta": 0.5},
    "panda": {},
    "baxter": {},
    "jaco": {},
}
