//! Why a scene file was refused, and where in the text: [`SceneError`] names the file, the line,
//! the column and the field.

/// Why a scene file was refused: where, which field, the value and what is allowed.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct SceneError {
    /// The file.
    pub file: String,
    /// 1-based line (0 when unknown).
    pub line: usize,
    /// 1-based column (0 when unknown).
    pub column: usize,
    /// The field, e.g. `colliders[1].shape.radius`.
    pub field: String,
    /// The offending value and what is allowed, or the parser's message.
    pub message: String,
}

impl std::fmt::Display for SceneError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "{}:{}:{}: `{}`: {}",
            self.file, self.line, self.column, self.field, self.message
        )
    }
}

impl std::error::Error for SceneError {}

/// The 1-based line and column of `key:` in entry `k` of `section` (from the entry's `name:`
/// line on), else that `name:` line.
pub(crate) fn locate_in_entry(text: &str, section: &str, k: usize, key: &str) -> (usize, usize) {
    let (name_line, name_column) = locate_after(text, Some(section), "name", k);
    let needle = format!("{key}:");
    text.lines()
        .enumerate()
        .skip(name_line.saturating_sub(1))
        .find_map(|(n, line)| line.find(&needle).map(|col| (n + 1, col + 1)))
        .unwrap_or((name_line, name_column))
}

/// The 1-based line and column of the `nth` (0-based) `key:` of `text`, else (0, 0), counting
/// only from the line of `section:` on (when given and found).
pub(crate) fn locate_after(
    text: &str,
    section: Option<&str>,
    key: &str,
    nth: usize,
) -> (usize, usize) {
    let start = section
        .and_then(|section| {
            let needle = format!("{section}:");
            text.lines().position(|line| line.contains(&needle))
        })
        .unwrap_or(0);
    let needle = format!("{key}:");
    text.lines()
        .enumerate()
        .skip(start)
        .filter_map(|(k, line)| line.find(&needle).map(|col| (k + 1, col + 1)))
        .nth(nth)
        .unwrap_or((0, 0))
}

/// The 1-based line and column just past the last character of `text` that is not white space.
pub(crate) fn end_of(text: &str) -> (usize, usize) {
    let body = text.trim_end();
    let line = body.lines().count().max(1);
    let column = body.lines().last().map_or(0, |l| l.chars().count()) + 1;
    (line, column)
}
