//! Macro values and the arithmetic of Custom Macro B, vacant included.
//!
//! Fanuc rules, as the Custom Macro B manual gives them:
//! - a vacant variable (`#0`, or one never set) used in arithmetic or a
//!   function is 0, so `#1+#2` with both vacant is 0, not vacant;
//! - `EQ` and `NE` tell vacant from 0: with `#1` vacant, `#1 EQ #0` is true
//!   and `#1 EQ 0` is false; `GT GE LT LE` take vacant as 0;
//! - assigning a vacant variable (`#2=#1`) keeps it vacant, and so does a
//!   sign or brackets around it (`X-#1`, `X[#1]`): such a word is left out of
//!   its block.

use crate::ast::{BinOp, Func};

/// A macro variable's value.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Value {
    /// `<vacant>`: never set, or `#0`.
    Vacant,
    /// A number.
    Num(f64),
}

impl Value {
    /// The value for arithmetic: vacant is 0.
    pub fn num(self) -> f64 {
        match self {
            Value::Vacant => 0.0,
            Value::Num(v) => v,
        }
    }

    /// `true` when vacant.
    pub fn is_vacant(self) -> bool {
        self == Value::Vacant
    }

    /// A condition's truth: non-zero is true, vacant is false.
    pub fn truth(self) -> bool {
        self.num() != 0.0
    }
}

fn from_bool(b: bool) -> Value {
    Value::Num(if b { 1.0 } else { 0.0 })
}

/// Largest integer that bitwise operators, BIN and BCD accept.
const MAX_INT: f64 = 99_999_999.0;

fn whole(v: f64, what: &str) -> Result<i64, String> {
    if v.fract() != 0.0 || v.abs() > MAX_INT {
        Err(format!("{what} needs whole numbers up to {MAX_INT}, got {v}"))
    } else {
        Ok(v as i64)
    }
}

/// Applies a binary operator.
pub fn binary(op: BinOp, a: Value, b: Value) -> Result<Value, String> {
    use BinOp::*;
    let (x, y) = (a.num(), b.num());
    // EQ and NE tell vacant from 0.
    let equal = || a == b || (!a.is_vacant() && !b.is_vacant() && x == y);
    let v = match op {
        Eq => return Ok(from_bool(equal())),
        Ne => return Ok(from_bool(!equal())),
        Gt => return Ok(from_bool(x > y)),
        Ge => return Ok(from_bool(x >= y)),
        Lt => return Ok(from_bool(x < y)),
        Le => return Ok(from_bool(x <= y)),
        Add => x + y,
        Sub => x - y,
        Mul => x * y,
        Div => {
            if y == 0.0 {
                return Err("division by zero".into());
            }
            x / y
        }
        Mod => {
            let (p, q) = (whole(x.round(), "MOD")?, whole(y.round(), "MOD")?);
            if q == 0 {
                return Err("MOD by zero".into());
            }
            (p % q) as f64
        }
        Pow => return pow(x, y),
        And => (whole(x, "AND")? & whole(y, "AND")?) as f64,
        Or => (whole(x, "OR")? | whole(y, "OR")?) as f64,
        Xor => (whole(x, "XOR")? ^ whole(y, "XOR")?) as f64,
    };
    finite(v, op.text())
}

/// Two values within this are equal for LinuxCNC's `EQ` and `NE`
/// (rs274ngc's `TOLERANCE_EQUAL`: `1 EQ 1.00005` is true, `1 EQ 1.0002` false).
pub const LINUXCNC_EQUAL: f64 = 0.0001;

/// Applies a binary operator as LinuxCNC (rs274ngc) does: `AND OR XOR`
/// are logical on reals (non-zero is true), `EQ NE` compare within
/// [`LINUXCNC_EQUAL`], `MOD` is the real remainder made non-negative
/// (`-7.5 MOD 2` is 0.5), `**` is a power. A LinuxCNC parameter is never
/// vacant: it reads 0 where it was never set.
pub fn binary_linuxcnc(op: BinOp, a: Value, b: Value) -> Result<Value, String> {
    use BinOp::*;
    let (x, y) = (a.num(), b.num());
    match op {
        And => Ok(from_bool(x != 0.0 && y != 0.0)),
        Or => Ok(from_bool(x != 0.0 || y != 0.0)),
        Xor => Ok(from_bool((x != 0.0) != (y != 0.0))),
        Eq => Ok(from_bool((x - y).abs() < LINUXCNC_EQUAL)),
        Ne => Ok(from_bool((x - y).abs() >= LINUXCNC_EQUAL)),
        Mod => {
            if y == 0.0 {
                return Err("MOD by zero".into());
            }
            let r = x % y;
            finite(if r < 0.0 { r + y.abs() } else { r }, "MOD")
        }
        _ => binary(op, Value::Num(x), Value::Num(y)),
    }
}

/// `x ** y`.
fn pow(x: f64, y: f64) -> Result<Value, String> {
    if x < 0.0 && y.fract() != 0.0 {
        return Err(format!("{x} ** {y}: a negative base needs a whole exponent"));
    }
    if x == 0.0 && y < 0.0 {
        return Err(format!("0 ** {y}: division by zero"));
    }
    finite(x.powf(y), "**")
}

/// Applies a function as LinuxCNC does where it differs from Fanuc: `FIX`
/// rounds down and `FUP` up (floor and ceiling, `FIX[-1.5]` is -2), and
/// `ATAN[y]/[x]` gives -180° to 180°.
pub fn call_linuxcnc(func: Func, a: Value, b: Option<Value>) -> Result<Value, String> {
    let x = a.num();
    match (func, b) {
        (Func::Fix, _) => Ok(Value::Num(x.floor())),
        (Func::Fup, _) => Ok(Value::Num(x.ceil())),
        (Func::Atan, Some(b)) => finite(x.atan2(b.num()).to_degrees(), "ATAN"),
        _ => call(func, Value::Num(x), b.map(|b| Value::Num(b.num()))),
    }
}

fn finite(v: f64, what: &str) -> Result<Value, String> {
    if v.is_finite() {
        Ok(Value::Num(v))
    } else {
        Err(format!("{what} gives a result that is not a finite number"))
    }
}

/// Rounds half away from zero, as the control's ROUND does.
pub fn round_half_away(v: f64) -> f64 {
    v.round()
}

/// Applies a function; angles in degrees. `b` is the second argument of
/// `ATAN[a]/[b]`, `ATAN[a,b]` and `POW[a,b]`.
pub fn call(func: Func, a: Value, b: Option<Value>) -> Result<Value, String> {
    use Func::*;
    let x = a.num();
    let v = match func {
        Sin => x.to_radians().sin(),
        Cos => x.to_radians().cos(),
        Tan => {
            let c = x.to_radians().cos();
            if c.abs() < 1e-12 {
                return Err(format!("TAN[{x}] is infinite"));
            }
            x.to_radians().sin() / c
        }
        Asin | Acos => {
            if !(-1.0..=1.0).contains(&x) {
                return Err(format!("{}[{x}]: the argument must lie between -1 and 1", func.name()));
            }
            if func == Asin {
                x.asin().to_degrees()
            } else {
                x.acos().to_degrees()
            }
        }
        Atan => match b {
            // Two arguments: the angle of the point (b, a), 0 to 360 degrees.
            Some(b) => {
                let d = x.atan2(b.num()).to_degrees();
                if d < 0.0 {
                    d + 360.0
                } else {
                    d
                }
            }
            None => x.atan().to_degrees(),
        },
        Sqrt => {
            if x < 0.0 {
                return Err(format!("SQRT[{x}]: square root of a negative number"));
            }
            x.sqrt()
        }
        Abs => x.abs(),
        Round => round_half_away(x),
        Fix => x.trunc(),
        Fup => {
            if x.fract() == 0.0 {
                x
            } else {
                x.trunc() + x.signum()
            }
        }
        Ln => {
            if x <= 0.0 {
                return Err(format!("LN[{x}]: logarithm of a number that is not positive"));
            }
            x.ln()
        }
        Exp => x.exp(),
        Pow => {
            let y = b.map_or(0.0, Value::num);
            if x < 0.0 && y.fract() != 0.0 {
                return Err(format!("POW[{x},{y}]: a negative base needs a whole exponent"));
            }
            if x == 0.0 && y < 0.0 {
                return Err("POW[0, negative]: division by zero".into());
            }
            x.powf(y)
        }
        Bin => {
            let mut n = whole(x, "BIN")?;
            if n < 0 {
                return Err(format!("BIN[{x}]: BCD values are not negative"));
            }
            let (mut out, mut scale) = (0i64, 1i64);
            while n > 0 {
                let digit = n & 0xF;
                if digit > 9 {
                    return Err(format!("BIN[{x}]: not a BCD value (a nibble is {digit})"));
                }
                out += digit * scale;
                scale *= 10;
                n >>= 4;
            }
            out as f64
        }
        Bcd => {
            let mut n = whole(x, "BCD")?;
            if n < 0 {
                return Err(format!("BCD[{x}]: negative numbers have no BCD form"));
            }
            let (mut out, mut shift) = (0i64, 0);
            while n > 0 {
                out |= (n % 10) << shift;
                shift += 4;
                n /= 10;
            }
            out as f64
        }
    };
    finite(v, func.name())
}

#[cfg(test)]
mod tests {
    use super::*;
    use Value::{Num, Vacant};

    fn f(func: Func, a: f64) -> f64 {
        call(func, Num(a), None).unwrap().num()
    }

    #[test]
    fn vacant_rules_follow_the_fanuc_table() {
        // Fanuc Custom Macro B: with #1 vacant / with #1 = 0.
        let cases = [
            (BinOp::Eq, Vacant, Vacant, true, Num(0.0), Vacant, false),
            (BinOp::Ne, Vacant, Num(0.0), true, Num(0.0), Num(0.0), false),
            (BinOp::Ge, Vacant, Vacant, true, Num(0.0), Vacant, true),
            (BinOp::Gt, Vacant, Num(0.0), false, Num(0.0), Num(0.0), false),
        ];
        for (op, a1, b1, want1, a2, b2, want2) in cases {
            assert_eq!(binary(op, a1, b1).unwrap().truth(), want1, "{op:?} vacant");
            assert_eq!(binary(op, a2, b2).unwrap().truth(), want2, "{op:?} zero");
        }
        assert_eq!(binary(BinOp::Eq, Vacant, Num(0.0)).unwrap(), Num(0.0));
        assert_eq!(binary(BinOp::Add, Vacant, Vacant).unwrap(), Num(0.0));
        assert_eq!(binary(BinOp::Mul, Vacant, Num(5.0)).unwrap(), Num(0.0));
    }

    #[test]
    fn arithmetic_and_errors() {
        assert_eq!(binary(BinOp::Mod, Num(17.0), Num(5.0)).unwrap(), Num(2.0));
        assert_eq!(binary(BinOp::And, Num(12.0), Num(10.0)).unwrap(), Num(8.0));
        assert_eq!(binary(BinOp::Or, Num(12.0), Num(10.0)).unwrap(), Num(14.0));
        assert_eq!(binary(BinOp::Xor, Num(12.0), Num(10.0)).unwrap(), Num(6.0));
        assert!(binary(BinOp::Div, Num(1.0), Num(0.0)).unwrap_err().contains("division by zero"));
        assert!(binary(BinOp::Div, Num(1.0), Vacant).is_err());
        assert!(binary(BinOp::And, Num(1.5), Num(1.0)).is_err());
        assert!(binary(BinOp::Mul, Num(1e300), Num(1e300)).is_err());
    }

    #[test]
    fn functions_match_the_manual() {
        assert!((f(Func::Sin, 30.0) - 0.5).abs() < 1e-15);
        assert!((f(Func::Cos, 60.0) - 0.5).abs() < 1e-15);
        assert!((f(Func::Tan, 45.0) - 1.0).abs() < 1e-15);
        assert!((f(Func::Asin, 0.5) - 30.0).abs() < 1e-12);
        assert!((f(Func::Acos, 0.5) - 60.0).abs() < 1e-12);
        assert!((f(Func::Atan, 1.0) - 45.0).abs() < 1e-12);
        let atan2 = |y: f64, x: f64| call(Func::Atan, Num(y), Some(Num(x))).unwrap().num();
        assert!((atan2(-1.0, -1.0) - 225.0).abs() < 1e-12);
        assert!((atan2(1.0, -1.0) - 135.0).abs() < 1e-12);
        assert_eq!(f(Func::Sqrt, 16.0), 4.0);
        assert_eq!(f(Func::Abs, -3.5), 3.5);
        assert_eq!(f(Func::Round, 1.5), 2.0);
        assert_eq!(f(Func::Round, -1.5), -2.0);
        assert_eq!(f(Func::Round, 1.4999), 1.0);
        assert_eq!(f(Func::Fix, 1.2), 1.0);
        assert_eq!(f(Func::Fix, -1.2), -1.0);
        assert_eq!(f(Func::Fup, 1.2), 2.0);
        assert_eq!(f(Func::Fup, -1.2), -2.0);
        assert_eq!(f(Func::Fup, 3.0), 3.0);
        assert!((f(Func::Ln, std::f64::consts::E) - 1.0).abs() < 1e-15);
        assert!((f(Func::Exp, 1.0) - std::f64::consts::E).abs() < 1e-15);
        assert_eq!(call(Func::Pow, Num(2.0), Some(Num(10.0))).unwrap(), Num(1024.0));
        assert_eq!(f(Func::Bcd, 12.0), 18.0);
        assert_eq!(f(Func::Bin, 18.0), 12.0);
        assert_eq!(f(Func::Bcd, 9999.0), 39321.0);
        assert_eq!(f(Func::Bin, 39321.0), 9999.0);
    }

    #[test]
    fn linuxcnc_operators_as_rs274_computes_them() {
        // Each figure as rs274 (LinuxCNC 2.9) printed it with (debug,…).
        let l = |op, a: f64, b: f64| binary_linuxcnc(op, Num(a), Num(b)).unwrap().num();
        assert_eq!(l(BinOp::Mod, 7.5, 2.0), 1.5);
        assert_eq!(l(BinOp::Mod, -7.5, 2.0), 0.5);
        assert_eq!(l(BinOp::Eq, 1.0, 1.00005), 1.0);
        assert_eq!(l(BinOp::Eq, 1.0, 1.0002), 0.0);
        assert_eq!(l(BinOp::Ne, 1.0, 1.00005), 0.0);
        assert_eq!(l(BinOp::And, 3.0, 0.5), 1.0);
        assert_eq!(l(BinOp::Or, 0.0, 0.0), 0.0);
        assert_eq!(l(BinOp::Xor, 1.0, 1.0), 0.0);
        assert_eq!(l(BinOp::Pow, 2.0, 3.0), 8.0);
        let c = |func, a: f64| call_linuxcnc(func, Num(a), None).unwrap().num();
        assert_eq!(c(Func::Fix, -1.5), -2.0);
        assert_eq!(c(Func::Fup, -1.5), -1.0);
        assert_eq!(c(Func::Round, -1.5), -2.0);
        assert_eq!(c(Func::Round, 2.5), 3.0);
        assert_eq!(call_linuxcnc(Func::Atan, Num(-1.0), Some(Num(-1.0))).unwrap(), Num(-135.0));
        assert!(binary_linuxcnc(BinOp::Mod, Num(1.0), Num(0.0)).is_err());
    }

    #[test]
    fn function_domain_errors() {
        for (func, a) in [
            (Func::Sqrt, -1.0),
            (Func::Asin, 1.5),
            (Func::Acos, -2.0),
            (Func::Ln, 0.0),
            (Func::Tan, 90.0),
            (Func::Bin, 10.0),
        ] {
            assert!(call(func, Num(a), None).is_err(), "{func:?}[{a}]");
        }
        assert!(call(Func::Pow, Num(-2.0), Some(Num(0.5))).is_err());
        assert_eq!(call(Func::Sqrt, Vacant, None).unwrap(), Num(0.0));
    }
}
