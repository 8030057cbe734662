//! The STATUSTEXTs of the parameter protocol: 50 bytes (MAVLink's `text`), numbers in three
//! significant digits. Texts are ASCII bytes in a fixed buffer, written by hand rather than with
//! `core::fmt`: its float formatting alone would link several KiB of flash (Grisu and Dragon)
//! for a message sent a few times per session, and a byte buffer is what STATUSTEXT carries.

/// STATUSTEXT `text` length.
pub const TEXT_LEN: usize = 50;

/// One STATUSTEXT's text: ASCII, at most [`TEXT_LEN`] bytes; what does not fit is cut.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Text {
    bytes: [u8; TEXT_LEN],
    len: usize,
}

impl Text {
    /// Empty.
    pub const fn new() -> Self {
        Self {
            bytes: [0; TEXT_LEN],
            len: 0,
        }
    }

    /// Appends `b` if there is room.
    fn push(&mut self, b: u8) {
        if let Some(slot) = self.bytes.get_mut(self.len) {
            *slot = b;
            self.len += 1;
        }
    }

    /// Appends as much of `s` as fits.
    fn push_str(&mut self, s: &str) {
        for b in s.bytes() {
            self.push(b);
        }
    }

    /// Length in bytes.
    pub fn len(&self) -> usize {
        self.len
    }

    /// STATUSTEXT's `text` field: the bytes, NUL-padded.
    pub fn field(&self) -> [u8; TEXT_LEN] {
        self.bytes
    }

    /// The text (up to the first byte that is not valid UTF-8, which an ASCII input never has).
    #[cfg(test)]
    pub fn as_str(&self) -> &str {
        let b = &self.bytes[..self.len];
        match core::str::from_utf8(b) {
            Ok(s) => s,
            Err(e) => core::str::from_utf8(&b[..e.valid_up_to()]).unwrap_or(""),
        }
    }
}

impl Default for Text {
    fn default() -> Self {
        Self::new()
    }
}

/// Appends `x` in at most three significant digits, trailing zeros dropped: `0.615`, `12.3`,
/// exponents outside `[1e-3, 1e5)` (`1.23e5`, `5e-4`), `nan`, `inf`, `-inf`.
/// Rounds half away from zero. Never fails: a full `out` keeps what fitted.
pub fn number(out: &mut Text, x: f32) {
    if x.is_nan() {
        out.push_str("nan");
        return;
    }
    if x < 0.0 {
        out.push(b'-');
    }
    let mut m = libm::fabsf(x);
    if m.is_infinite() {
        out.push_str("inf");
        return;
    }
    if m == 0.0 {
        out.push(b'0');
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
        out.push(b'e');
        if e < 0 {
            out.push(b'-');
        }
        uint(out, e.unsigned_abs(), 1);
    }
}

/// Writes `int.frac` with `frac` on `decimals` digits, trailing zeros (and a bare point) dropped.
fn fraction(out: &mut Text, int: u32, mut frac: u32, mut decimals: u32) {
    while decimals > 0 && frac.is_multiple_of(10) {
        frac /= 10;
        decimals -= 1;
    }
    uint(out, int, 1);
    if decimals > 0 {
        out.push(b'.');
        uint(out, frac, decimals);
    }
}

/// Appends `n` in decimal, zero-padded to at least `digits` digits. Written out rather than
/// with `core::fmt`, which this crate does not link otherwise.
fn uint(out: &mut Text, mut n: u32, digits: u32) {
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
        out.push(b);
    }
}

/// `"{name} refused: {reason}"`, cut at 50 bytes.
pub fn refused(name: &str, reason: &str) -> Text {
    let mut t = Text::new();
    t.push_str(name);
    t.push_str(" refused: ");
    t.push_str(reason);
    t
}

/// `"{name} refused: {condition} {lhs}<{rhs}"` with the relation the two numbers actually
/// have (`<`, `=`, `>`; `rhs` left out when NaN). The numbers always fit: when the whole text
/// does not, `refused` is dropped (`"{name}: {condition} …"`), then the condition name is cut
/// (the event log has it whole).
pub fn condition(name: &str, condition: &str, lhs: f32, rhs: f32) -> Text {
    let mut tail = Text::new();
    tail.push(b' ');
    number(&mut tail, lhs);
    if !rhs.is_nan() {
        let relation = if lhs < rhs {
            b'<'
        } else if lhs > rhs {
            b'>'
        } else {
            b'='
        };
        tail.push(relation);
        number(&mut tail, rhs);
    }
    let mut t = refused(name, "");
    if t.len() + condition.len() + tail.len() > TEXT_LEN {
        t = Text::new();
        t.push_str(name);
        t.push_str(": ");
    }
    let room = TEXT_LEN.saturating_sub(t.len() + tail.len());
    for &b in condition.as_bytes().iter().take(room) {
        t.push(b);
    }
    for &b in &tail.bytes[..tail.len] {
        t.push(b);
    }
    t
}

/// `"{name} refused: range {min}..{max}"`.
pub fn out_of_range(name: &str, min: f32, max: f32) -> Text {
    let mut t = refused(name, "range ");
    number(&mut t, min);
    t.push_str("..");
    number(&mut t, max);
    t
}

/// `"param unknown: {id}"`, the name as sent (up to 16 bytes) with non-printable bytes as `?`.
pub fn unknown(id: &[u8]) -> Text {
    let mut t = Text::new();
    t.push_str("param unknown: ");
    for &b in id.iter().take(16).take_while(|&&b| b != 0) {
        t.push(if b.is_ascii_graphic() { b } else { b'?' });
    }
    t
}

/// `"param index {index} unknown"`.
pub fn unknown_index(index: i16) -> Text {
    let mut t = Text::new();
    t.push_str("param index ");
    if index < 0 {
        t.push(b'-');
    }
    uint(&mut t, u32::from(index.unsigned_abs()), 1);
    t.push_str(" unknown");
    t
}

#[cfg(test)]
mod tests {
    use super::*;

    fn n(x: f32) -> std::string::String {
        let mut s = Text::new();
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
            t.as_str()
                .starts_with("SAF_DISARM_AGE: theorem1.thrust_bound"),
            "{t:?}"
        );
        assert!(t.as_str().ends_with(" 7.25>7"), "{t:?}");
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
