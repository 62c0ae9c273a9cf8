(G61 exact stop and G64 cutting mode - LinuxCNC G64 P Q blending - change how)
(moves join, not where they go; #4015 reads the active one)
G21 G90 G17
G61 G00 X0. Y0. Z5.
#1 = #4015
G64 P0.01 Q0.005 G01 X10. F600.
#2 = #4015
G01 X10. Y10. Z[#1 + #2]
M30
