"""Visual materials shared by every furniture model: wood tones, laminates, metal.

These are finishes: how a part looks. What it weighs comes from its
construction (construction.py), which the family code assigns.
"""

# name -> (rgba, specular, shininess)
MATERIALS = {
    "wood_light": ((0.86, 0.72, 0.52, 1), 0.2, 0.2),
    "wood_medium": ((0.66, 0.46, 0.28, 1), 0.2, 0.2),
    "wood_dark": ((0.36, 0.23, 0.13, 1), 0.2, 0.3),
    "birch": ((0.92, 0.84, 0.68, 1), 0.2, 0.2),
    "white_laminate": ((0.94, 0.94, 0.92, 1), 0.4, 0.5),
    "black_laminate": ((0.12, 0.12, 0.13, 1), 0.4, 0.5),
    "metal": ((0.62, 0.64, 0.67, 1), 0.8, 0.8),
}
