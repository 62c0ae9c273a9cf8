//! Numbers as program text, for every stage that writes some: the
//! interpreter's kept blocks and messages, the writer's words, the measuring
//! programs and the text rewrites.

/// `10^digits` for the decimals a program may have, 0 to 6.
pub(crate) const POW10: [u64; 7] = [1, 10, 100, 1_000, 10_000, 100_000, 1_000_000];

/// A number as hand-made program text writes it: `digits` decimals,
/// trailing zeros dropped, a decimal point always (`2.`, `-0.05`, never
/// `-0.`).
pub(crate) fn number(v: f64, digits: usize) -> String {
    let s = format!("{v:.digits$}");
    let s = if s.contains('.') { s.trim_end_matches('0').to_string() } else { s + "." };
    if s == "-0." {
        "0.".into()
    } else {
        s
    }
}

/// Writes `n` units of the last of `digits` decimals: trailing zeros
/// trimmed, never `-0`, and with `point` a decimal point even on whole
/// numbers.
pub(crate) fn push_fixed(out: &mut String, n: i64, digits: u32, point: bool) {
    if n < 0 {
        out.push('-');
    }
    let a = n.unsigned_abs();
    let p = POW10[digits as usize];
    push_uint(out, a / p);
    let frac = a % p;
    if frac != 0 {
        out.push('.');
        push_padded(out, frac, digits);
        // Trailing zeros go; a non-zero digit stops it before the point.
        while out.ends_with('0') {
            out.pop();
        }
    } else if point {
        out.push('.');
    }
}

/// Writes `v` in decimal.
pub(crate) fn push_uint(out: &mut String, v: u64) {
    push_padded(out, v, 1);
}

/// Writes `v` with at least `width` digits (leading zeros).
pub(crate) fn push_padded(out: &mut String, mut v: u64, width: u32) {
    let mut buf = [b'0'; 20];
    let mut i = buf.len();
    while v > 0 || buf.len() - i < width as usize {
        i -= 1;
        buf[i] = b'0' + (v % 10) as u8;
        v /= 10;
    }
    for &b in &buf[i..] {
        out.push(char::from(b));
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fixed_numbers_lose_their_trailing_zeros() {
        let mut out = String::new();
        push_fixed(&mut out, -1500, 3, true);
        out.push(' ');
        push_fixed(&mut out, 2000, 3, false);
        out.push(' ');
        push_padded(&mut out, 7, 4);
        assert_eq!(out, "-1.5 2 0007");
    }
}
