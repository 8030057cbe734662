//! The STATUSTEXTs of the parameter protocol: 50 bytes (MAVLink's `text`), numbers in three
//! significant digits. Numbers are written by hand: `core::fmt` (and its float formatting)
//! would link several KiB of flash for a message sent a few times per session.

use heapless::String;

/// STATUSTEXT `text` length.
pub const TEXT_LEN: usize = 50;

/// One STATUSTEXT's text.
pub type Text = String<TEXT_LEN>;

/// Appends `x` in at most three significant digits, trailing zeros dropped: `0.615`, `12.3`,
/// exponents outside `[1e-3, 1e5)` (`1.23e5`, `5e-4`), `nan`, `inf`, `-inf`.
/// Rounds half away from zero. Never fails: a full `out` keeps what fitted.
pub fn number<const N: usize>(out: &mut String<N>, x: f32) {
    if x.is_nan() {
        let _ = out.push_str("nan");
        return;
    }
    if x < 0.0 {
        let _ = out.push('-');
    }
    let mut m = libm::fabsf(x);
    if m.is_infinite() {
        let _ = out.push_str("inf");
        return;
    }
    if m == 0.0 {
        let _ = out.push('0');
        return;
    }
    // |x| = m · 10^e with m in [1, 10); at most 45 steps either way for a finite f32, each
    // exact to half an ulp, far below the third digit.
    let mut e = 0i32;
    while m >= 10.0 {
        m /= 10.0;
        e += 1;
    }
    while m < 1.0 {
        m *= 10.0;
        e -= 1;
    }
    // Three digits `d` with |x| ≈ d · 10^(e − 2).
    let mut d = libm::roundf(m * 100.0) as u32;
    if d >= 1000 {
        d = 100;
        e += 1;
    }
    if (-3..5).contains(&e) {
        if e >= 2 {
            uint(out, d * 10u32.pow((e - 2) as u32), 1);
        } else {
            let decimals = (2 - e) as u32;
            let scale = 10u32.pow(decimals);
            fraction(out, d / scale, d % scale, decimals);
        }
    } else {
        fraction(out, d / 100, d % 100, 2);
        let _ = out.push('e');
        if e < 0 {
            let _ = out.push('-');
        }
        uint(out, e.unsigned_abs(), 1);
    }
}

/// Writes `int.frac` with `frac` on `decimals` digits, trailing zeros (and a bare point) dropped.
fn fraction<const N: usize>(out: &mut String<N>, int: u32, mut frac: u32, mut decimals: u32) {
    while decimals > 0 && frac % 10 == 0 {
        frac /= 10;
        decimals -= 1;
    }
    uint(out, int, 1);
    if decimals > 0 {
        let _ = out.push('.');
        uint(out, frac, decimals);
    }
}

/// Appends `n` in decimal, zero-padded to at least `digits` digits. Written out rather than
/// with `core::fmt`, which this crate does not link otherwise.
fn uint<const N: usize>(out: &mut String<N>, mut n: u32, digits: u32) {
    let mut buf = [b'0'; 10];
    let mut i = buf.len();
    while n > 0 || buf.len() - i < digits as usize {
        i -= 1;
        buf[i] = b'0' + (n % 10) as u8;
        n /= 10;
        if i == 0 {
            break;
        }
    }
    for &b in &buf[i..] {
        let _ = out.push(b as char);
    }
}

/// `"{name} refused: {reason}"`, cut at 50 bytes.
pub fn refused(name: &str, reason: &str) -> Text {
    let mut t = Text::new();
    push_cut(&mut t, name);
    push_cut(&mut t, " refused: ");
    push_cut(&mut t, reason);
    t
}

/// `"{name} refused: {condition} {lhs}<{rhs}"` with the relation the two numbers actually
/// have (`<`, `=`, `>`; `rhs` left out when NaN). The numbers always fit: when the whole text
/// does not, `refused` is dropped (`"{name}: {condition} …"`), then the condition name is cut
/// (the event log has it whole).
pub fn condition(name: &str, condition: &str, lhs: f32, rhs: f32) -> Text {
    let mut tail = Text::new();
    let _ = tail.push(' ');
    number(&mut tail, lhs);
    if !rhs.is_nan() {
        let relation = if lhs < rhs {
            '<'
        } else if lhs > rhs {
            '>'
        } else {
            '='
        };
        let _ = tail.push(relation);
        number(&mut tail, rhs);
    }
    let mut t = refused(name, "");
    if t.len() + condition.len() + tail.len() > TEXT_LEN {
        t.clear();
        push_cut(&mut t, name);
        push_cut(&mut t, ": ");
    }
    let room = TEXT_LEN.saturating_sub(t.len() + tail.len());
    push_cut(&mut t, &condition[..floor_char_boundary(condition, room)]);
    push_cut(&mut t, &tail);
    t
}

/// `"{name} refused: range {min}..{max}"`.
pub fn out_of_range(name: &str, min: f32, max: f32) -> Text {
    let mut t = refused(name, "range ");
    number(&mut t, min);
    push_cut(&mut t, "..");
    number(&mut t, max);
    t
}

/// `"param unknown: {id}"`, the name as sent (up to 16 bytes) with non-printable bytes as `?`.
pub fn unknown(id: &[u8]) -> Text {
    let mut t = Text::new();
    push_cut(&mut t, "param unknown: ");
    for &b in id.iter().take(16).take_while(|&&b| b != 0) {
        let _ = t.push(if b.is_ascii_graphic() { b as char } else { '?' });
    }
    t
}

/// `"param index {index} unknown"`.
pub fn unknown_index(index: i16) -> Text {
    let mut t = Text::new();
    push_cut(&mut t, "param index ");
    if index < 0 {
        let _ = t.push('-');
    }
    uint(&mut t, u32::from(index.unsigned_abs()), 1);
    push_cut(&mut t, " unknown");
    t
}

/// Appends as much of `s` as fits (at a character boundary).
fn push_cut(t: &mut Text, s: &str) {
    let room = TEXT_LEN - t.len();
    let _ = t.push_str(&s[..floor_char_boundary(s, room)]);
}

/// The largest `i <= max` that is a character boundary of `s`.
fn floor_char_boundary(s: &str, max: usize) -> usize {
    let mut i = max.min(s.len());
    while !s.is_char_boundary(i) {
        i -= 1;
    }
    i
}

#[cfg(test)]
mod tests {
    use super::*;

    fn n(x: f32) -> std::string::String {
        let mut s = String::<24>::new();
        number(&mut s, x);
        s.as_str().into()
    }

    /// Three significant digits, trailing zeros dropped, exponents outside [1e-3, 1e5).
    #[test]
    fn numbers_are_compact() {
        let cases: [(f32, &str); 19] = [
            (1e-10, "1e-10"),
            (3.4e38, "3.4e38"),
            (-0.0123, "-0.0123"),
            (0.0, "0"),
            (0.5, "0.5"),
            (0.615, "0.615"),
            (0.6149, "0.615"),
            (-1.0, "-1"),
            (12.34, "12.3"),
            (100.0, "100"),
            (999.6, "1000"),
            (34.19432, "34.2"),
            (12345.0, "12300"),
            (123456.0, "1.23e5"),
            (0.001, "0.001"),
            (0.00049, "4.9e-4"),
            (f32::NAN, "nan"),
            (f32::NEG_INFINITY, "-inf"),
            (9.9951, "10"),
        ];
        for (x, want) in cases {
            assert_eq!(n(x), want, "{x}");
        }
        // Every result parses back within half a unit of the third digit.
        for k in -40..40 {
            let x = 1.2345f32 * 10f32.powi(k / 4) * (1.0 + k as f32 * 0.37);
            let got: f32 = n(x).parse().unwrap();
            assert!((got - x).abs() <= 5.01e-3 * x.abs(), "{x} -> {got}");
        }
    }

    /// The condition text keeps both numbers when the names are long, and fits 50 bytes.
    #[test]
    fn condition_text_keeps_the_numbers() {
        let t = condition(
            "SAF_DISARM_AGE",
            "theorem1.thrust_bound_within_actuator",
            7.25,
            7.0,
        );
        assert_eq!(t.len(), TEXT_LEN);
        assert!(
            t.starts_with("SAF_DISARM_AGE: theorem1.thrust_bound"),
            "{t}"
        );
        assert!(t.ends_with(" 7.25>7"), "{t}");
        let t = condition("POS_KP", "theorem2.torque_max_yaw", 0.5, 0.61);
        assert_eq!(
            t.as_str(),
            "POS_KP refused: theorem2.torque_max_yaw 0.5<0.61"
        );
        let t = condition("LIM_TAU_Z", "theorem2.torque_max_yaw", 0.057, 0.1134);
        assert_eq!(t.as_str(), "LIM_TAU_Z: theorem2.torque_max_yaw 0.057<0.113");
        let t = condition("POS_MP", "M_p", 9.9, f32::NAN);
        assert_eq!(t.as_str(), "POS_MP refused: M_p 9.9");
    }

    /// A garbled name is shown with its non-printable bytes replaced.
    #[test]
    fn unknown_names_are_printable() {
        let mut id = [0u8; 16];
        id[..4].copy_from_slice(b"AB\x01C");
        assert_eq!(unknown(&id).as_str(), "param unknown: AB?C");
        assert_eq!(unknown(&[b'Z'; 16]).len(), 15 + 16);
        assert_eq!(unknown_index(-7).as_str(), "param index -7 unknown");
        assert_eq!(
            unknown_index(i16::MIN).as_str(),
            "param index -32768 unknown"
        );
    }
}
