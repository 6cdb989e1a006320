// A parametric torus and a parametric twisted band (raydiance's side-by-side with POV-Ray 3.7,
// docs/povray.md). In POV-Ray's functions u and v are x and y.
#version 3.7;
global_settings { assumed_gamma 1 }
camera { location <0, 3, -7> right x*image_width/image_height angle 40 look_at <0, 0.5, 0> }
light_source { <-20, 30, -25> color rgb 1 }
background { color rgb <0.5, 0.6, 0.8> }
plane { y, -0.5 pigment { checker color rgb 0.9, color rgb 0.3 } }
parametric {
  function { (1 + 0.35 * cos(v)) * cos(u) }
  function { 0.35 * sin(v) }
  function { (1 + 0.35 * cos(v)) * sin(u) }
  <0, 0>, <2 * pi, 2 * pi>
  contained_by { box { <-1.4, -0.4, -1.4>, <1.4, 0.4, 1.4> } }
  max_gradient 2 accuracy 0.005 precompute 12, x, y, z
  translate <-1.4, 0.1, 0> pigment { color rgb <0.9, 0.3, 0.2> }
}
parametric {
  function { u }
  function { v * cos(u * 2) }
  function { v * sin(u * 2) }
  <-1, -0.5>, <1, 0.5>
  contained_by { box { <-1, -0.5, -0.5>, <1, 0.5, 0.5> } }
  max_gradient 2 accuracy 0.005 precompute 12, x, y, z
  rotate -30*y translate <1.5, 0.6, 0> pigment { color rgb <0.2, 0.5, 0.9> }
}
