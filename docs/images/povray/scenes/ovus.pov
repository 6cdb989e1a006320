// Ovus in both of its cases, the top radius below and above the bottom one (raydiance's
// side-by-side with POV-Ray 3.7, docs/povray.md).
#version 3.7;
global_settings { assumed_gamma 1 }
camera { location <0, 2, -7> right x*image_width/image_height angle 40 look_at <0, 0.7, 0> }
light_source { <-20, 30, -25> color rgb 1 }
background { color rgb <0.5, 0.6, 0.8> }
plane { y, 0 pigment { checker color rgb 0.9, color rgb 0.3 } }
ovus { 1, 0.6 translate <-1.4, 1, 0> pigment { color rgb <0.9, 0.3, 0.2> } }
ovus { 0.5, 0.8 rotate -30*z translate <1.3, 0.5, 0> pigment { color rgb <0.2, 0.5, 0.9> } }
