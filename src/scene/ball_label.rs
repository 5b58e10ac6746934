//! A ball's own label (`label = "..."` in a scene's `[[ball]]`; an imported glTF file's
//! material name): one line of text drawn under the ball where the scene's `labels` are
//! on (`crate::labels`), shortened with an ellipsis to the ball's column.
//!
//! Held inline (a fixed number of bytes) so that a [`super::Ball`] stays `Copy`.

/// Most bytes of UTF-8 a ball's label holds.
pub const MAX_BALL_LABEL_BYTES: usize = 64;

/// The ellipsis that ends a shortened label.
pub const ELLIPSIS: char = '\u{2026}';

/// One line of text, 1 to [`MAX_BALL_LABEL_BYTES`] bytes of UTF-8, no control character,
/// not blank.
#[derive(Clone, Copy, PartialEq, Eq)]
pub struct BallLabel {
    len: u8,
    bytes: [u8; MAX_BALL_LABEL_BYTES],
}

const _: () = assert!(MAX_BALL_LABEL_BYTES <= u8::MAX as usize);

impl BallLabel {
    /// `text` as a label, or why it cannot be one (a scene file's check).
    pub(crate) fn new(text: &str) -> Result<Self, String> {
        if text.trim().is_empty() {
            return Err("a ball's label is blank: give it some text, or leave `label` out".into());
        }
        if text.chars().any(char::is_control) {
            return Err(
                "a ball's label is one line: it holds a control character (a line break?)".into(),
            );
        }
        if text.len() > MAX_BALL_LABEL_BYTES {
            return Err(format!(
                "a ball's label is {} bytes long, more than the {MAX_BALL_LABEL_BYTES} it may be",
                text.len()
            ));
        }
        let mut bytes = [0; MAX_BALL_LABEL_BYTES];
        bytes[..text.len()].copy_from_slice(text.as_bytes());
        Ok(Self {
            len: text.len() as u8,
            bytes,
        })
    }

    /// Any text made a label (an imported name): control characters become spaces, the
    /// ends are trimmed, and a text over [`MAX_BALL_LABEL_BYTES`] is cut at a character
    /// and ends with [`ELLIPSIS`]; `None` for a blank text.
    pub(crate) fn shortened(text: &str) -> Option<Self> {
        let line: String = text
            .chars()
            .map(|c| if c.is_control() { ' ' } else { c })
            .collect();
        let line = line.trim();
        if line.len() <= MAX_BALL_LABEL_BYTES {
            return Self::new(line).ok();
        }
        let room = MAX_BALL_LABEL_BYTES - ELLIPSIS.len_utf8();
        let mut cut = room;
        while !line.is_char_boundary(cut) {
            cut -= 1;
        }
        Self::new(&format!("{}{ELLIPSIS}", line[..cut].trim_end())).ok()
    }

    /// The text.
    pub fn as_str(&self) -> &str {
        // Built only from a `&str` cut at a character boundary.
        std::str::from_utf8(&self.bytes[..self.len as usize]).unwrap_or_default()
    }
}

impl std::fmt::Debug for BallLabel {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{:?}", self.as_str())
    }
}

impl std::fmt::Display for BallLabel {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.as_str())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_label_is_one_line_of_bounded_text() {
        assert_eq!(BallLabel::new("Gold").unwrap().as_str(), "Gold");
        for bad in ["", "   ", "two\nlines", "tab\there"] {
            let e = BallLabel::new(bad).unwrap_err();
            assert!(!e.contains('\n'), "{e}");
        }
        let long = "x".repeat(MAX_BALL_LABEL_BYTES + 1);
        assert!(BallLabel::new(&long).unwrap_err().contains("65 bytes"));
        assert!(BallLabel::new(&long[1..]).is_ok());
    }

    #[test]
    fn an_imported_name_is_shortened_at_a_character_with_an_ellipsis() {
        assert_eq!(
            BallLabel::shortened(" a\nb ").unwrap().as_str(),
            "a b",
            "control characters become spaces, the ends trimmed"
        );
        assert!(BallLabel::shortened("\n\t").is_none());
        // 40 two-byte characters: 80 bytes, cut to whole characters under the limit.
        let long = "\u{e9}".repeat(40);
        let l = BallLabel::shortened(&long).unwrap();
        assert!(l.as_str().len() <= MAX_BALL_LABEL_BYTES);
        assert!(l.as_str().ends_with(ELLIPSIS));
        assert!(long.starts_with(l.as_str().trim_end_matches(ELLIPSIS)));
    }
}
