(fuzz: #5341 read past the G59 offsets, index out of bounds)
#1=#5341
#5341=1.
M30
