(TEST: step-limit=1000)
N10 #1=#1+1.
GOTO10
M30
