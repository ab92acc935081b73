"""Visual materials shared by every furniture model: wood tones, laminates, metal."""

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

# kg per cubic metre, for the mass of parts made of each material
DENSITY = {
    "metal": 2700.0,  # hollow steel and aluminium profiles average out near aluminium
}
DEFAULT_DENSITY = 600.0   # particleboard and solid pine
