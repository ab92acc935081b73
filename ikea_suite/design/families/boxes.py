"""Storage boxes: a bottom panel with four walls standing on it."""

from ikea_suite.design import blueprint as bp


def open_box(name, variant, length=0.40, width=0.30, height=0.15, board=0.012,
             material="wood_light"):
  """Long walls run the full length; short walls fit between them."""
  furniture = bp.Blueprint(name, "box", "open", variant,
                           f"{length:.2f} x {width:.2f} x {height:.2f} m open storage box")
  bottom = furniture.add_part("bottom", (0, 0, board / 2), geoms=[
      bp.Geom("box", (length / 2, width / 2, board / 2), material=material)])
  wall_z = board + height / 2
  for i, sy in enumerate((1, -1)):
    y = sy * (width / 2 - board / 2)
    wall = furniture.add_part(f"long_wall{i}", (0, y, wall_z), geoms=[
        bp.Geom("box", (length / 2, board / 2, height / 2), material=material)])
    furniture.connect(bottom, wall, (0, y, board), up=(0, 0, 1), forward=(1, 0, 0),
                      type_a="bottom_long_slot", type_b="long_wall_bottom", twists_deg=(0, 180))
  for i, sx in enumerate((1, -1)):
    x = sx * (length / 2 - board / 2)
    inner = width / 2 - board
    wall = furniture.add_part(f"short_wall{i}", (x, 0, wall_z), geoms=[
        bp.Geom("box", (board / 2, inner, height / 2), material=material)])
    furniture.connect(bottom, wall, (x, 0, board), up=(0, 0, 1), forward=(1, 0, 0),
                      type_a="bottom_short_slot", type_b="short_wall_bottom", twists_deg=(0, 180))
  return furniture


def variants():
  return [open_box("box_open_kuggis", "kuggis")]
