# The rooms of scripts/continuation-check and scripts/fast-mode-check, sourced by both:
#   write_check_rooms DIR        writes DIR/<room>.yaml for the rooms defined here
#   check_room_args ROOM DIR     the simulate arguments of ROOM: its room or mesh, source,
#                                listener and response length
# cr2 (BRAS CR2, the bundled mesh) and sample (the demo's sample room) come from data/;
# carpeted, hall, classroom, corridor, studio, church, office and gym are defined here. Needs $here,
# the repository.
write_check_rooms() {
  cat > "$1/carpeted.yaml" <<'YAML'
frame: room
room_box: {size_m: [9.0, 6.0, 3.0], has_ceiling: true}
surfaces:
  floor: {material: carpet_thick}
  ceiling: {material: acoustic_ceiling_tiles}
  wall_x_min: {material: concrete_painted}
  wall_x_max: {material: plaster_smooth}
  wall_y_min: {material: glass_window}
  wall_y_max: {material: brick_bare}
YAML
  cat > "$1/hall.yaml" <<'YAML'
frame: room
room_box: {size_m: [12.0, 4.0, 5.0], has_ceiling: true}
surfaces:
  floor: {material: parquet_on_concrete}
  ceiling: {material: plaster_smooth}
  wall_x_min: {material: mineral_wool_panel}
  wall_x_max: {material: curtain_heavy}
  wall_y_min: {material: plasterboard_on_studs}
  wall_y_max: {material: concrete_painted}
objects:
  - {label: table, material: wood_panel, center_m: [6.0, 2.0, 0.38], size_m: [2.4, 1.0, 0.75]}
YAML
  cat > "$1/church.yaml" <<'YAML'
frame: room
room_box: {size_m: [20.0, 12.0, 9.0], has_ceiling: true}
surfaces:
  floor: {material: marble}
  ceiling: {material: wood_ceiling}
  wall_x_min: {material: brick_bare}
  wall_x_max: {material: glass_window}
  wall_y_min: {material: concrete_block_painted}
  wall_y_max: {material: brick_bare}
objects:
  - {label: pews_left, material: chair_wooden, center_m: [10.0, 3.5, 0.45], size_m: [10.0, 4.0, 0.9]}
  - {label: pews_right, material: chair_wooden, center_m: [10.0, 8.5, 0.45], size_m: [10.0, 4.0, 0.9]}
YAML

  cat > "$1/classroom.yaml" <<'YAML'
frame: room
room_box: {size_m: [9.0, 7.0, 3.2], has_ceiling: true}
surfaces:
  floor: {material: linoleum_on_concrete}
  ceiling: {material: acoustic_ceiling_tiles}
  wall_x_min: {material: whiteboard}
  wall_x_max: {material: plaster_smooth}
  wall_y_min: {material: glass_window}
  wall_y_max: {material: concrete_block_painted}
objects:
  - {label: desks_front, material: wood_panel, center_m: [3.5, 3.5, 0.38], size_m: [1.2, 5.0, 0.75]}
  - {label: desks_middle, material: wood_panel, center_m: [5.3, 3.5, 0.38], size_m: [1.2, 5.0, 0.75]}
  - {label: desks_back, material: wood_panel, center_m: [7.1, 3.5, 0.38], size_m: [1.2, 5.0, 0.75]}
YAML
  cat > "$1/corridor.yaml" <<'YAML'
frame: room
room_box: {size_m: [30.0, 2.4, 3.0], has_ceiling: true}
surfaces:
  floor: {material: polished_concrete_or_tile}
  ceiling: {material: acoustic_ceiling_tiles}
  wall_x_min: {material: door_wood}
  wall_x_max: {material: glass_window}
  wall_y_min: {material: plasterboard_on_studs}
  wall_y_max: {material: plasterboard_on_studs}
YAML
  # office and gym: added to check the fast mode's track receiver, whose radius was chosen
  # on the sample and carpeted rooms; never used to choose anything.
  cat > "$1/office.yaml" <<'YAML'
frame: room
room_box: {size_m: [4.5, 3.5, 2.7], has_ceiling: true}
surfaces:
  floor: {material: carpet_on_concrete}
  ceiling: {material: acoustic_ceiling_tiles}
  wall_x_min: {material: glass_double_glazing}
  wall_x_max: {material: plasterboard_on_studs}
  wall_y_min: {material: plasterboard_on_studs}
  wall_y_max: {material: bookshelf_with_books}
objects:
  - {label: desk, material: wood_panel, center_m: [2.8, 1.2, 0.37], size_m: [1.6, 0.8, 0.74]}
YAML
  cat > "$1/gym.yaml" <<'YAML'
frame: room
room_box: {size_m: [24.0, 14.0, 7.0], has_ceiling: true}
surfaces:
  floor: {material: wood_floor}
  ceiling: {material: metal}
  wall_x_min: {material: concrete_block_painted}
  wall_x_max: {material: mineral_wool_panel}
  wall_y_min: {material: glass_window}
  wall_y_max: {material: concrete_block_coarse}
YAML
  cat > "$1/studio.yaml" <<'YAML'
frame: room
room_box: {size_m: [5.0, 4.0, 2.7], has_ceiling: true}
surfaces:
  floor: {material: wood_floor}
  ceiling: {material: mineral_wool_panel}
  wall_x_min: {material: fabric_wall_panel}
  wall_x_max: {material: plasterboard_on_studs}
  wall_y_min: {material: fabric_wall_panel}
  wall_y_max: {material: plasterboard_on_studs}
objects:
  - {label: sofa, material: fabric_upholstered_seat, center_m: [2.5, 3.45, 0.45], size_m: [2.0, 0.9, 0.9]}
YAML
}

check_room_args() {
  case "$1" in
    cr2) echo "--mesh $here/data/bras_cr2/geometry/cr2_scene9.ac --y-up --source 0.931 -2.547 0.723 --listener -0.993 1.426 1.230 --duration 2" ;;
    sample) echo "--room $here/data/sample_room/visible.yaml --source 4.6 2.9 1.5 --listener 2.7 2.1 1.4 --duration 1.5" ;;
    carpeted) echo "--room $2/carpeted.yaml --source 2.0 1.5 1.5 --listener 6.8 4.1 1.2 --duration 1.5" ;;
    hall) echo "--room $2/hall.yaml --source 2.5 1.2 1.6 --listener 9.0 2.8 1.3 --duration 2" ;;
    classroom) echo "--room $2/classroom.yaml --source 1.2 3.5 1.6 --listener 6.2 1.6 1.2 --duration 1.5" ;;
    corridor) echo "--room $2/corridor.yaml --source 3.0 1.2 1.6 --listener 16.0 0.9 1.5 --duration 2" ;;
    studio) echo "--room $2/studio.yaml --source 1.2 1.0 1.2 --listener 3.6 2.1 1.1 --duration 1" ;;
    office) echo "--room $2/office.yaml --source 1.0 2.6 1.2 --listener 3.4 2.5 1.2 --duration 1" ;;
    gym) echo "--room $2/gym.yaml --source 5.0 7.0 1.6 --listener 16.0 4.5 1.6 --duration 3" ;;
    church) echo "--room $2/church.yaml --source 3.0 6.0 2.0 --listener 15.0 4.0 1.6 --duration 3" ;;
    *) echo "unknown room '$1' (cr2, carpeted, sample, hall, classroom, corridor, studio, church, office, gym)" >&2; exit 2 ;;
  esac
}

