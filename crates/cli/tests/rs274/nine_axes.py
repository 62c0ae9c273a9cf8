"""Runs a G-code file through LinuxCNC's preview parser (the `gcode` module
of AXIS, Debian package linuxcnc-uspace) on a machine with all nine axes,
and prints every motion's end point in machine coordinates:

    KIND LINE X Y Z A B C U V W

KIND is rapid, feed, cw, ccw or probe; X Y Z U V W in mm, A B C in degrees.
The last line is `result N` (N <= gcode.MIN_ERROR: the program ran) or
`error LINE MESSAGE`.

usage: python3 nine_axes.py FILE PARAMETER_FILE
"""

import math
import sys

import gcode

MM = 25.4  # the parser hands lengths over in inches


class Canon:
    """A canon that keeps what a motion's end is, nothing drawn."""

    parameter_file = ""

    def __init__(self):
        self.g5x = [0.0] * 9
        self.g92 = [0.0] * 9
        self.rotation = 0.0
        self.plane = 1
        self.line = 0
        self.motions = []

    # What the parser asks of the machine.
    def get_axis_mask(self):
        return 0x1FF  # X Y Z A B C U V W

    def get_external_length_units(self):
        return 1.0 / MM

    def get_external_angular_units(self):
        return 1.0

    def get_block_delete(self):
        return False

    def get_tool(self, number):
        # tool, nine offsets, diameter, front and back angle, orientation
        return (number,) + (0.0,) * 12 + (0,)

    def check_abort(self):
        return False

    # What it tells.
    def next_line(self, state):
        self.line = state.sequence_number

    def set_g5x_offset(self, index, *offset):
        self.g5x = [v or 0.0 for v in offset] + [0.0] * (9 - len(offset))

    def set_g92_offset(self, *offset):
        self.g92 = [v or 0.0 for v in offset] + [0.0] * (9 - len(offset))

    def set_xy_rotation(self, degrees):
        self.rotation = degrees

    def set_plane(self, plane):
        self.plane = plane

    select_plane = set_plane

    def machine(self, p):
        """Program coordinates to machine coordinates: the G92 offset, the
        XY rotation, then the coordinate system's offset."""
        p = [p[k] + self.g92[k] for k in range(9)]
        if self.rotation:
            s, c = math.sin(math.radians(self.rotation)), math.cos(math.radians(self.rotation))
            p[0], p[1] = p[0] * c - p[1] * s, p[0] * s + p[1] * c
        p = [p[k] + self.g5x[k] for k in range(9)]
        return [v * MM if k < 3 or k >= 6 else v for k, v in enumerate(p)]

    def record(self, kind, p):
        self.motions.append((kind, self.line, self.machine(list(p))))

    def straight_traverse(self, *p):
        self.record("rapid", p)

    def straight_feed(self, *p):
        self.record("feed", p)

    def straight_probe(self, *p):
        self.record("probe", p)

    def arc_feed(self, first, second, c1, c2, rotation, axis, a, b, c, u, v, w):
        if self.plane == 2:  # YZ
            xyz = [axis, first, second]
        elif self.plane == 3:  # XZ
            xyz = [second, axis, first]
        else:  # XY
            xyz = [first, second, axis]
        self.record("ccw" if rotation > 0 else "cw", xyz + [a, b, c, u, v, w])

    def __getattr__(self, name):
        # Every other call (spindle, coolant, feed rate, comments): nothing.
        if name.startswith("__"):
            raise AttributeError(name)
        return lambda *args, **kwargs: None


def main():
    canon = Canon()
    canon.parameter_file = sys.argv[2]
    try:
        result, line = gcode.parse(sys.argv[1], canon, "", "")
    except RuntimeError as e:
        print("error 0 %s" % e)
        return
    for kind, at, p in canon.motions:
        print(kind, at, " ".join("%.9f" % v for v in p))
    if result > gcode.MIN_ERROR:
        print("error %d %s" % (line, gcode.strerror(result)))
    else:
        print("result %d" % result)


main()
