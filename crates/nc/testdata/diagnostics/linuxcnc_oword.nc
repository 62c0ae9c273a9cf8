o100 sub
G01 X1. F100.
o100 endsub
M30
