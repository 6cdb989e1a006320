// Sphere sweeps along POV-Ray's three splines (raydiance's side-by-side with POV-Ray 3.7,
// docs/povray.md): linear, cubic and b-spline, their radii changing along them.
#version 3.7;
global_settings { assumed_gamma 1 }
camera { location <0, 2, -8> right x*image_width/image_height angle 45 look_at <0, 0.2, 0> }
light_source { <-20, 30, -25> color rgb 1 }
background { color rgb <0.5, 0.6, 0.8> }
plane { y, -2.5 pigment { checker color rgb 0.9, color rgb 0.3 } }
sphere_sweep { linear_spline 4, <-3, 1.2, 0>, 0.2, <-1.5, 2, 0>, 0.5, <0, 1.3, 0.5>, 0.1, <1.5, 1.8, 0>, 0.35
  pigment { color rgb <0.9, 0.3, 0.2> } }
sphere_sweep { cubic_spline 6, <-3, 0, 0>, 0.1, <-2.5, 0, 0>, 0.2, <-1.2, 0.8, 0>, 0.4, <0, -0.3, 0>, 0.15,
  <1.2, 0.6, 0>, 0.45, <2, 0, 0>, 0.2 tolerance 0.001
  pigment { color rgb <0.3, 0.8, 0.3> } }
sphere_sweep { b_spline 5, <-2, -1.8, 0>, 0.3, <-1, -0.6, 0>, 0.5, <0, -1.8, 0>, 0.1, <1, -0.6, 0>, 0.6, <2, -1.8, 0>, 0.3
  rotate 20*y pigment { color rgb <0.2, 0.5, 0.9> } }
