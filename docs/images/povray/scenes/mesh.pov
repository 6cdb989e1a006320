// A mesh of flat triangles and a mesh of smooth triangles (raydiance's side-by-side with
// POV-Ray 3.7, docs/povray.md): the same octahedron, faceted on the left, and on the right with
// each vertex's normal pointing away from the centre, so it shades round.
#version 3.7;
global_settings { assumed_gamma 1 }
camera { location <0, 2.5, -7> right x*image_width/image_height angle 40 look_at <0, 0.6, 0> }
light_source { <-20, 30, -25> color rgb 1 }
background { color rgb <0.5, 0.6, 0.8> }
plane { y, 0 pigment { checker color rgb 0.9, color rgb 0.3 } }
#declare Flat = mesh {
  triangle { <1, 0, 0>, <0, 1, 0>, <0, 0, -1> } triangle { <0, 0, -1>, <0, 1, 0>, <-1, 0, 0> }
  triangle { <-1, 0, 0>, <0, 1, 0>, <0, 0, 1> } triangle { <0, 0, 1>, <0, 1, 0>, <1, 0, 0> }
  triangle { <1, 0, 0>, <0, -1, 0>, <0, 0, -1> } triangle { <0, 0, -1>, <0, -1, 0>, <-1, 0, 0> }
  triangle { <-1, 0, 0>, <0, -1, 0>, <0, 0, 1> } triangle { <0, 0, 1>, <0, -1, 0>, <1, 0, 0> }
}
#declare Smooth = mesh {
  smooth_triangle { <1, 0, 0>, <1, 0, 0>, <0, 1, 0>, <0, 1, 0>, <0, 0, -1>, <0, 0, -1> }
  smooth_triangle { <0, 0, -1>, <0, 0, -1>, <0, 1, 0>, <0, 1, 0>, <-1, 0, 0>, <-1, 0, 0> }
  smooth_triangle { <-1, 0, 0>, <-1, 0, 0>, <0, 1, 0>, <0, 1, 0>, <0, 0, 1>, <0, 0, 1> }
  smooth_triangle { <0, 0, 1>, <0, 0, 1>, <0, 1, 0>, <0, 1, 0>, <1, 0, 0>, <1, 0, 0> }
  smooth_triangle { <1, 0, 0>, <1, 0, 0>, <0, -1, 0>, <0, -1, 0>, <0, 0, -1>, <0, 0, -1> }
  smooth_triangle { <0, 0, -1>, <0, 0, -1>, <0, -1, 0>, <0, -1, 0>, <-1, 0, 0>, <-1, 0, 0> }
  smooth_triangle { <-1, 0, 0>, <-1, 0, 0>, <0, -1, 0>, <0, -1, 0>, <0, 0, 1>, <0, 0, 1> }
  smooth_triangle { <0, 0, 1>, <0, 0, 1>, <0, -1, 0>, <0, -1, 0>, <1, 0, 0>, <1, 0, 0> }
}
object { Flat rotate 30*y translate <-1.3, 1, 0> pigment { color rgb <0.9, 0.3, 0.2> } }
object { Smooth rotate 30*y translate <1.3, 1, 0> pigment { color rgb <0.2, 0.5, 0.9> } }
