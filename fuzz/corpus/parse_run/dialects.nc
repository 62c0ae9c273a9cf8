o100 sub
#<x>=1
o100 endsub
$H
G1 X1 (comment
;semi
/N5 G0 X0.
