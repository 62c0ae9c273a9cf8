#<depth>=2.
G01 Z-#<depth> F100.
M30
