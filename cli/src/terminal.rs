//! What the command writes to the terminal (stderr): every message passes
//! through [`escaped`], so a control character in an input (a label, a
//! `--select`, a file name, a value quoted in an error) is shown as an
//! escape (`\u{1b}`) instead of acting on the terminal (an escape sequence
//! can set the window title, move the cursor or hide text).

use std::borrow::Cow;

/// `text` with every control character except the newline written as
/// Rust's `\u{…}` escape; borrowed unchanged when it has none.
///
/// ```
/// use laminar_brdf::terminal::escaped;
/// assert_eq!(escaped("21/avg/exp"), "21/avg/exp");
/// assert_eq!(escaped("x\u{1b}]0;title\u{7}"), "x\\u{1b}]0;title\\u{7}");
/// assert_eq!(escaped("two\nlines\r"), "two\nlines\\r");
/// ```
pub fn escaped(text: &str) -> Cow<'_, str> {
    if !text.chars().any(needs_escape) {
        return Cow::Borrowed(text);
    }
    let mut out = String::with_capacity(text.len() + 8);
    for c in text.chars() {
        if needs_escape(c) {
            out.extend(c.escape_default());
        } else {
            out.push(c);
        }
    }
    Cow::Owned(out)
}

fn needs_escape(c: char) -> bool {
    c.is_control() && c != '\n'
}

/// `eprintln!` through [`escaped`]: the only way the command writes a
/// message to stderr.
#[macro_export]
macro_rules! note {
    ($($arg:tt)*) => {
        eprintln!("{}", $crate::terminal::escaped(&format!($($arg)*)))
    };
}
