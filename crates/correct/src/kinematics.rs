//! The machine's kinematic chains: which axes carry the tool and which the
//! work, in order, and where the tool's tip is.
//!
//! Each side is a chain from the machine's base outwards: the tool side
//! ends at the spindle, the work side at the part. A linear axis moves what
//! it carries along its direction; a rotary axis turns it about its axis
//! through its pivot (right hand, degrees). Commands are what a program
//! says: where the tool is relative to the part. So a work-side axis moves
//! the part against its command: a table commanded to X+10 carries the part
//! 10 mm towards −X, and the tool ends 10 mm further +X on the part; a C
//! spindle commanded to C90 turns the part −90°.
//!
//! [`Kinematics::forward`] gives the tool tip in part coordinates for a
//! command; [`Kinematics::inverse`] the linear commands that put the tip
//! at a point with the rotary axes where the program has them (indexed
//! 3+2 work: with the rotaries fixed the tip is an affine function of the
//! three linear commands, so the inverse is one 3 × 3 solve).

use crate::{Error, ErrorKind};

/// Axis letters in command order: X Y Z A B C.
pub const AXES: [char; 6] = ['X', 'Y', 'Z', 'A', 'B', 'C'];

/// How an axis moves what it carries.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Motion {
    /// Along a unit direction, mm.
    Linear {
        /// Unit direction in the machine frame.
        direction: [f64; 3],
    },
    /// About a unit axis through a pivot, degrees.
    Rotary {
        /// Unit axis in the machine frame.
        axis: [f64; 3],
        /// A point of the axis, mm.
        pivot: [f64; 3],
    },
}

/// One axis of a chain.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Axis {
    /// Its index in X Y Z A B C.
    pub index: usize,
    /// How it moves.
    pub motion: Motion,
}

/// A machine's two chains and its tool tip.
#[derive(Clone, Debug, PartialEq)]
pub struct Kinematics {
    /// Axes that carry the tool, from the base out.
    pub tool: Vec<Axis>,
    /// Axes that carry the work, from the base out.
    pub work: Vec<Axis>,
    /// The tool tip (the reference tool's edge) with every axis at zero,
    /// machine frame, mm.
    pub tip: [f64; 3],
}

/// A rigid motion: `p ↦ r·p + t`.
#[derive(Clone, Copy, Debug)]
struct Rigid {
    r: [[f64; 3]; 3],
    t: [f64; 3],
}

impl Rigid {
    const IDENTITY: Rigid = Rigid { r: [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]], t: [0.0; 3] };

    fn apply(&self, p: [f64; 3]) -> [f64; 3] {
        std::array::from_fn(|i| self.r[i][0] * p[0] + self.r[i][1] * p[1] + self.r[i][2] * p[2] + self.t[i])
    }

    /// `self ∘ other`: other first.
    fn then_inner(&self, other: &Rigid) -> Rigid {
        let r = std::array::from_fn(|i| std::array::from_fn(|j| (0..3).map(|k| self.r[i][k] * other.r[k][j]).sum()));
        Rigid { r, t: self.apply(other.t) }
    }

    fn inverse(&self) -> Rigid {
        let r: [[f64; 3]; 3] = std::array::from_fn(|i| std::array::from_fn(|j| self.r[j][i]));
        let t = std::array::from_fn(|i| -(0..3).map(|k| r[i][k] * self.t[k]).sum::<f64>());
        Rigid { r, t }
    }

    /// The motion of `axis` at `value` (mm or degrees).
    fn of(motion: Motion, value: f64) -> Rigid {
        match motion {
            Motion::Linear { direction: d } => {
                Rigid { t: [d[0] * value, d[1] * value, d[2] * value], ..Rigid::IDENTITY }
            }
            Motion::Rotary { axis: u, pivot: c } => {
                // Rodrigues: R = cos·I + sin·[u]× + (1 − cos)·u uᵀ.
                let (s, k) = value.to_radians().sin_cos();
                let cross = [[0.0, -u[2], u[1]], [u[2], 0.0, -u[0]], [-u[1], u[0], 0.0]];
                let r: [[f64; 3]; 3] = std::array::from_fn(|i| {
                    std::array::from_fn(|j| {
                        let id = if i == j { 1.0 } else { 0.0 };
                        k * id + s * cross[i][j] + (1.0 - k) * u[i] * u[j]
                    })
                });
                // About the pivot: p ↦ R (p − c) + c.
                let rc = Rigid { r, t: [0.0; 3] }.apply(c);
                Rigid { r, t: [c[0] - rc[0], c[1] - rc[1], c[2] - rc[2]] }
            }
        }
    }
}

impl Kinematics {
    /// A 3-axis mill: X, Y and Z carry the tool along the machine's axes.
    pub fn mill() -> Kinematics {
        let linear = |index: usize| {
            let mut direction = [0.0; 3];
            direction[index] = 1.0;
            Axis { index, motion: Motion::Linear { direction } }
        };
        Kinematics { tool: vec![linear(0), linear(1), linear(2)], work: Vec::new(), tip: [0.0; 3] }
    }

    /// The thermal and wear report's Swiss-type mill-turn: the milling spindle carries X, Z
    /// and a B tilt about Y through `b_pivot`; the turning side carries Y
    /// and C (about Z through the origin); `tip` is the tool tip with every
    /// axis at zero.
    pub fn mill_turn(b_pivot: [f64; 3], tip: [f64; 3]) -> Kinematics {
        let linear = |index: usize, direction: [f64; 3]| Axis { index, motion: Motion::Linear { direction } };
        let rotary =
            |index: usize, axis: [f64; 3], pivot: [f64; 3]| Axis { index, motion: Motion::Rotary { axis, pivot } };
        Kinematics {
            tool: vec![linear(0, [1.0, 0.0, 0.0]), linear(2, [0.0, 0.0, 1.0]), rotary(4, [0.0, 1.0, 0.0], b_pivot)],
            work: vec![linear(1, [0.0, 1.0, 0.0]), rotary(5, [0.0, 0.0, 1.0], [0.0; 3])],
            tip,
        }
    }

    /// Checks the chains: X, Y and Z once each and linear, every other axis
    /// at most once, unit directions, finite numbers.
    pub fn check(&self) -> Result<(), Error> {
        let bad = |m: String| Err(Error::new(ErrorKind::BadKinematics, m));
        let mut seen = [false; 6];
        for a in self.tool.iter().chain(&self.work) {
            if a.index >= 6 {
                return bad(format!("axis index {} is not one of X Y Z A B C", a.index));
            }
            let name = AXES[a.index];
            if std::mem::replace(&mut seen[a.index], true) {
                return bad(format!("axis {name} is on the machine twice"));
            }
            let (v, p) = match a.motion {
                Motion::Linear { direction } => (direction, [0.0; 3]),
                Motion::Rotary { axis, pivot } => (axis, pivot),
            };
            let len = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
            if !v.iter().chain(&p).all(|x| x.is_finite()) || (len - 1.0).abs() > 1e-9 {
                return bad(format!("axis {name}: its direction must be a unit vector of finite numbers, got {v:?}"));
            }
            if (a.index < 3) != matches!(a.motion, Motion::Linear { .. }) {
                return bad(format!("axis {name} must be {}", if a.index < 3 { "linear" } else { "rotary" }));
            }
        }
        if let Some(k) = (0..3).find(|&k| !seen[k]) {
            return bad(format!("the machine has no {} axis: X, Y and Z are needed", AXES[k]));
        }
        if !self.tip.iter().all(|x| x.is_finite()) {
            return bad("the tool tip must be finite".into());
        }
        // The three linear axes must span space at every rotary position
        // the inverse meets; at zero at least:
        if self.linear_jacobian(&[0.0; 6]).is_none() {
            return bad("the linear axes do not span space: two are parallel".into());
        }
        Ok(())
    }

    /// The axes this machine has, by index.
    pub fn has(&self, index: usize) -> bool {
        self.tool.iter().chain(&self.work).any(|a| a.index == index)
    }

    /// Where the tool's frame (the machine frame with every axis at zero)
    /// lies in part coordinates for the commands `c`.
    fn pose(&self, c: &[f64; 6]) -> Rigid {
        let chain = |axes: &[Axis], sign: f64| {
            axes.iter().fold(Rigid::IDENTITY, |m, a| m.then_inner(&Rigid::of(a.motion, sign * c[a.index])))
        };
        let tool = chain(&self.tool, 1.0);
        // A work-side axis moves the part against its command.
        let work = chain(&self.work, -1.0);
        work.inverse().then_inner(&tool)
    }

    /// The tool tip in part coordinates for the commands `c` (X Y Z mm,
    /// A B C degrees; axes the machine lacks are ignored).
    pub fn forward(&self, c: &[f64; 6]) -> [f64; 3] {
        self.pose(c).apply(self.tip)
    }

    /// The tool axis (unit, from the tip toward the spindle) in part
    /// coordinates for the commands `c`: the machine's +Z with every axis
    /// at zero, turned by the rotary axes.
    pub fn tool_axis(&self, c: &[f64; 6]) -> [f64; 3] {
        let r = self.pose(c).r;
        [r[0][2], r[1][2], r[2][2]]
    }

    /// The linear commands (X Y Z) that put the tip at `target` with the
    /// rotary axes at `c[3..]`; the rest of `c` is the starting guess and
    /// is replaced. `None` where the linear axes do not span space there.
    pub fn inverse(&self, target: [f64; 3], c: &[f64; 6]) -> Option<[f64; 6]> {
        let j = self.linear_jacobian(c)?;
        let mut out = *c;
        let at = self.forward(c);
        let step = solve3(j, [target[0] - at[0], target[1] - at[1], target[2] - at[2]])?;
        for k in 0..3 {
            out[k] += step[k];
        }
        Some(out)
    }

    /// ∂tip/∂(X Y Z) at `c`, columns by axis (exact: the tip is affine in
    /// the linear commands); `None` when singular.
    pub fn linear_jacobian(&self, c: &[f64; 6]) -> Option<[[f64; 3]; 3]> {
        let at = self.forward(c);
        let mut j = [[0.0; 3]; 3];
        for k in 0..3 {
            let mut d = *c;
            d[k] += 1.0;
            let p = self.forward(&d);
            for i in 0..3 {
                j[i][k] = p[i] - at[i];
            }
        }
        let det = det3(j);
        (det.abs() > 1e-9).then_some(j)
    }
}

fn det3(m: [[f64; 3]; 3]) -> f64 {
    m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0])
        + m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0])
}

/// `m x = b` by Cramer's rule; `None` when singular.
pub fn solve3(m: [[f64; 3]; 3], b: [f64; 3]) -> Option<[f64; 3]> {
    let d = det3(m);
    if d.abs() < 1e-300 || !d.is_finite() {
        return None;
    }
    Some(std::array::from_fn(|k| {
        let mut mk = m;
        for i in 0..3 {
            mk[i][k] = b[i];
        }
        det3(mk) / d
    }))
}
