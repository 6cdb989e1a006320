// lemon.pov for POV-Ray 3.7, which has no lemon: POV-Ray 3.8's lemon of end radii A and B along
// y from 0 to 1 with inner radius R has its arc centred at (-C, V), and is where a sphere, a
// quartic and the slab between its ends overlap (tests/povray_oracle.rs, lemon_as_csg).
#version 3.7;
global_settings { assumed_gamma 1 }
camera { location <0, 2, -7> right x*image_width/image_height angle 40 look_at <0, 0.8, 0> }
light_source { <-20, 30, -25> color rgb 1 }
background { color rgb <0.5, 0.6, 0.8> }
plane { y, 0 pigment { checker color rgb 0.9, color rgb 0.3 } }
#macro Lemon37(A, B, R)
  #local F = sqrt(4 * R * R / (pow(B - A, 2) + 1) - 1);
  #local C = (F - A - B) / 2;
  #local V = ((B - A) * F + 1) / 2;
  #local K = C * C - R * R;
  #local L = -(2 * K - 4 * C * C);
  intersection {
    quartic { <-1, 0, 0, 0, -2, 0, 0, -2, 0, L, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0,
               -1, 0, 0, -2, 0, -2 * K, 0, 0, 0, 0, -1, 0, L, 0, -K * K> sturm translate V * y }
    sphere { <0, V, 0>, sqrt(R * R - C * C) }
    box { <-3, 0, -3>, <3, 1, 3> }
  }
#end
object { Lemon37(0.3, 0.2, 0.9) scale 1.6 rotate 20*z translate <-1.2, 0.2, 0>
  pigment { color rgb <0.9, 0.8, 0.1> } }
object { Lemon37(0, 0.4, 1.2) scale <1.2, 1.6, 1.2> rotate -30*x translate <1.3, 0.3, 0>
  pigment { color rgb <0.2, 0.5, 0.9> } }
