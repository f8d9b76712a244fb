#!/usr/bin/env python3
"""Writes the Collada test meshes of test/scene/robots (run it here to regenerate them).

box_mm_z_up.dae: a 100 x 200 x 300 mm box, <unit meter="0.001">, Z_UP: read as 0.1 x 0.2 x 0.3 m
along x, y, z. box_m_y_up.dae: a 0.1 x 0.2 x 0.3 m box along its own x, y, z with Y_UP declared:
read turned by +90 deg about x, its 0.2 m edge (its up axis) along z. not_a_mesh.dae: malformed
on purpose (a mismatched element), which assimp cannot read.
"""


def box(unit, up, size):
    sx, sy, sz = [s / 2 for s in size]
    v = [(-sx, -sy, -sz), (sx, -sy, -sz), (sx, sy, -sz), (-sx, sy, -sz),
         (-sx, -sy, sz), (sx, -sy, sz), (sx, sy, sz), (-sx, sy, sz)]
    # Counter-clockwise seen from outside.
    tris = [(0, 2, 1), (0, 3, 2), (4, 5, 6), (4, 6, 7), (0, 1, 5), (0, 5, 4),
            (1, 2, 6), (1, 6, 5), (2, 3, 7), (2, 7, 6), (3, 0, 4), (3, 4, 7)]
    pos = " ".join(f"{c:g}" for p in v for c in p)
    idx = " ".join(str(i) for t in tris for i in t)
    return f'''<?xml version="1.0" encoding="utf-8"?>
<!-- Written by generate_boxes.py: a box of {size[0]:g} x {size[1]:g} x {size[2]:g} units of {unit} m, {up}. -->
<COLLADA xmlns="http://www.collada.org/2005/11/COLLADASchema" version="1.4.1">
  <asset>
    <unit name="unit" meter="{unit}"/>
    <up_axis>{up}</up_axis>
  </asset>
  <library_geometries>
    <geometry id="box" name="box">
      <mesh>
        <source id="box-positions">
          <float_array id="box-positions-array" count="{len(v) * 3}">{pos}</float_array>
          <technique_common>
            <accessor source="#box-positions-array" count="{len(v)}" stride="3">
              <param name="X" type="float"/>
              <param name="Y" type="float"/>
              <param name="Z" type="float"/>
            </accessor>
          </technique_common>
        </source>
        <vertices id="box-vertices">
          <input semantic="POSITION" source="#box-positions"/>
        </vertices>
        <triangles count="{len(tris)}">
          <input semantic="VERTEX" source="#box-vertices" offset="0"/>
          <p>{idx}</p>
        </triangles>
      </mesh>
    </geometry>
  </library_geometries>
  <library_visual_scenes>
    <visual_scene id="scene" name="scene">
      <node id="box-node" name="box-node">
        <instance_geometry url="#box"/>
      </node>
    </visual_scene>
  </library_visual_scenes>
  <scene>
    <instance_visual_scene url="#scene"/>
  </scene>
</COLLADA>
'''


if __name__ == "__main__":
    with open("box_mm_z_up.dae", "w") as f:
        f.write(box("0.001", "Z_UP", (100, 200, 300)))
    with open("box_m_y_up.dae", "w") as f:
        f.write(box("1", "Y_UP", (0.1, 0.2, 0.3)))
    with open("not_a_mesh.dae", "w") as f:
        f.write('<?xml version="1.0"?>\n'
                '<COLLADA version="1.4.1"><asset><up_axis>Z_UP</asset></COLLADA>\n')
