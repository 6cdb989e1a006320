// Two lemons (raydiance's side-by-side with POV-Ray 3.7, docs/povray.md). POV-Ray 3.7 has no
// lemon (3.8 added it): lemon-povray37.pov is the same two solids written as CSG, which
// POV-Ray renders for the comparison.
#version 3.7;
global_settings { assumed_gamma 1 }
camera { location <0, 2, -7> right x*image_width/image_height angle 40 look_at <0, 0.8, 0> }
light_source { <-20, 30, -25> color rgb 1 }
background { color rgb <0.5, 0.6, 0.8> }
plane { y, 0 pigment { checker color rgb 0.9, color rgb 0.3 } }
lemon { <0, 0, 0>, 0.3, <0, 1, 0>, 0.2, 0.9 scale 1.6 rotate 20*z translate <-1.2, 0.2, 0>
  pigment { color rgb <0.9, 0.8, 0.1> } }
lemon { <0, 0, 0>, 0, <0, 1, 0>, 0.4, 1.2 scale <1.2, 1.6, 1.2> rotate -30*x translate <1.3, 0.3, 0>
  pigment { color rgb <0.2, 0.5, 0.9> } }
