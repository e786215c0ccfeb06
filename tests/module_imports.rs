//! No module of `crates/` imports a module that imports it back, directly or through others.
//!
//! For every crate under `crates/*/src` this test builds the graph of its module files and their
//! imports, and fails naming every cycle (`a.rs -> b.rs -> a.rs`, paths relative to the crate's
//! `src/`) with, for each import on a cycle, the line that makes it. It reads the sources with std
//! only; no compiler is involved, so the definitions below are what it checks:
//!
//! - A *module* is a source file: `foo.rs` or `foo/mod.rs` is the module `foo`, `foo/bar.rs` the
//!   module `foo::bar`, and the crate root (`lib.rs` or `main.rs`) the module `crate`. An inline
//!   `mod name { ... }` belongs to the file it is written in.
//! - Module A *imports* module B when A's code, outside comments and string and character literals
//!   and outside `#[cfg(test)] mod name { ... }` blocks (whose `use super::*` is fine), names B
//!   through a path:
//!   - `use` declarations, `pub use` and glob `use` included, with their `{...}` groups expanded
//!     (nested groups too; `self` in a group names the group's prefix);
//!   - any other path in code with at least two segments (`crate::b::Item`, `super::Item`,
//!     `self::child::f()`, `crate::Item`);
//!   - a path starting with `crate`, `super` (any number of them), `self`, or the name of a module
//!     declared in A's scope (`mod child;` or `mod child { ... }`: `child::item`, `use child::X;`).
//!     Paths starting with anything else (`std::`, `bevy::`, `sph_core::`, a type's `Self::`, an
//!     enum's `Kind::Variant`) name nothing in the crate and are ignored.
//!
//!   A path names the deepest module file it reaches: `crate::render::stages::count_cells::X` is
//!   `render/stages/count_cells.rs`, `crate::api::SphParams` is `api.rs`, `super::SphRun` in
//!   `render/stages/density.rs` is `render/stages/mod.rs`, `crate::SphSystems` is the crate root.
//! - A declaration `mod child;` or `pub mod child;` is not an import: a parent must declare its
//!   children. Imports of a module by itself (`super::*` inside an inline module) are ignored.
//! - `#[path = "..."]` attributes on `mod` declarations are not followed (the crates use none).
//!
//! The parser's own tests (`parser_*`) run on small strings and are independent of the tree.

use std::collections::{BTreeMap, BTreeSet};
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

/// The crates checked, one test each; `every_crate_is_checked` fails when a crate is added.
const CRATES: [&str; 3] = ["bevy_sph_fluid", "sph_bench", "sph_core"];

/// At most this many elementary cycles are listed per crate (every cycle's modules are also
/// named by their strongly connected component, so nothing is hidden by the cap).
const MAX_CYCLES_LISTED: usize = 500;

#[test]
fn sph_core_has_no_import_cycles() {
    assert_no_cycles("sph_core");
}

#[test]
fn bevy_sph_fluid_has_no_import_cycles() {
    assert_no_cycles("bevy_sph_fluid");
}

#[test]
fn sph_bench_has_no_import_cycles() {
    assert_no_cycles("sph_bench");
}

#[test]
fn every_crate_is_checked() {
    let crates_dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("crates");
    let mut found: Vec<String> = std::fs::read_dir(&crates_dir)
        .unwrap_or_else(|e| panic!("reading {}: {e}", crates_dir.display()))
        .filter_map(|entry| entry.ok())
        .filter(|entry| entry.path().join("src").is_dir())
        .map(|entry| entry.file_name().to_string_lossy().into_owned())
        .collect();
    found.sort();
    assert_eq!(found, CRATES, "add a test for every crate under crates/");
}

fn assert_no_cycles(name: &str) {
    let src = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("crates")
        .join(name)
        .join("src");
    let files = source_files(&src);
    assert!(
        files.len() > 1,
        "{}: found {} source files",
        src.display(),
        files.len()
    );
    let sources: Vec<(String, String)> = files
        .iter()
        .map(|path| {
            let text = std::fs::read_to_string(path)
                .unwrap_or_else(|e| panic!("reading {}: {e}", path.display()));
            let relative = path.strip_prefix(&src).expect("a file under src/");
            (relative.to_string_lossy().replace('\\', "/"), text)
        })
        .collect();
    let graph = ImportGraph::build(&sources);
    let report = graph.cycle_report();
    assert!(
        report.is_empty(),
        "crates/{name}/src: modules that import a module that imports them back\n{report}"
    );
}

/// Every `.rs` file under `dir`, sorted.
fn source_files(dir: &Path) -> Vec<PathBuf> {
    let mut out = Vec::new();
    let mut stack = vec![dir.to_path_buf()];
    while let Some(dir) = stack.pop() {
        let entries =
            std::fs::read_dir(&dir).unwrap_or_else(|e| panic!("reading {}: {e}", dir.display()));
        for entry in entries {
            let path = entry.expect("a directory entry").path();
            if path.is_dir() {
                stack.push(path);
            } else if path.extension().is_some_and(|ext| ext == "rs") {
                out.push(path);
            }
        }
    }
    out.sort();
    out
}

/// The module path of a source file relative to `src/`: `lib.rs` -> `[]`, `a/mod.rs` -> `[a]`,
/// `a/b.rs` -> `[a, b]`.
fn module_path(relative: &str) -> Vec<String> {
    let stem = relative.strip_suffix(".rs").unwrap_or(relative);
    let mut segments: Vec<String> = stem.split('/').map(str::to_owned).collect();
    if segments.len() == 1 && (segments[0] == "lib" || segments[0] == "main") {
        return Vec::new();
    }
    if segments.last().is_some_and(|last| last == "mod") {
        segments.pop();
    }
    segments
}

/// The modules of one crate and the imports between them.
struct ImportGraph {
    /// File paths relative to `src/`, sorted; the node ids are indices into this.
    files: Vec<String>,
    /// `edges[a][b]`: the first line of `a` that imports `b`, and the path it names.
    edges: Vec<BTreeMap<usize, (usize, String)>>,
}

impl ImportGraph {
    /// Builds the graph of `(path relative to src/, source text)` pairs.
    fn build(sources: &[(String, String)]) -> Self {
        let mut sources: Vec<&(String, String)> = sources.iter().collect();
        sources.sort_by(|a, b| a.0.cmp(&b.0));
        let roots = sources
            .iter()
            .filter(|(path, _)| module_path(path).is_empty())
            .count();
        assert!(
            roots <= 1,
            "a crate with both lib.rs and main.rs is not supported"
        );
        let files: Vec<String> = sources.iter().map(|(path, _)| path.clone()).collect();
        let modules: BTreeMap<Vec<String>, usize> = files
            .iter()
            .enumerate()
            .map(|(id, path)| (module_path(path), id))
            .collect();
        let mut edges = vec![BTreeMap::new(); files.len()];
        for (from, (path, text)) in sources.iter().enumerate() {
            let scan = scan(text);
            let here = module_path(path);
            for reference in &scan.references {
                let Some(target) = resolve(&here, reference, &scan.declared, &modules) else {
                    continue;
                };
                if target != from {
                    edges[from]
                        .entry(target)
                        .or_insert_with(|| (reference.line, reference.segments.join("::")));
                }
            }
        }
        Self { files, edges }
    }

    /// Every elementary cycle, each starting at its smallest node, sorted.
    fn cycles(&self) -> Vec<Vec<usize>> {
        let component = self.components();
        let mut cycles = Vec::new();
        for start in 0..self.files.len() {
            let mut path = vec![start];
            let mut on_path = vec![false; self.files.len()];
            on_path[start] = true;
            self.cycles_from(start, &component, &mut path, &mut on_path, &mut cycles);
        }
        cycles.sort();
        cycles
    }

    /// Depth-first search for paths back to `path[0]` through larger nodes of its component.
    fn cycles_from(
        &self,
        start: usize,
        component: &[usize],
        path: &mut Vec<usize>,
        on_path: &mut [bool],
        cycles: &mut Vec<Vec<usize>>,
    ) {
        if cycles.len() > MAX_CYCLES_LISTED {
            return;
        }
        let last = *path.last().expect("a non-empty path");
        for &next in self.edges[last].keys() {
            if next == start {
                cycles.push(path.clone());
            } else if next > start && !on_path[next] && component[next] == component[start] {
                path.push(next);
                on_path[next] = true;
                self.cycles_from(start, component, path, on_path, cycles);
                on_path[next] = false;
                path.pop();
            }
        }
    }

    /// Strongly connected components (Tarjan): the component id of every node.
    fn components(&self) -> Vec<usize> {
        struct Tarjan<'a> {
            edges: &'a [BTreeMap<usize, (usize, String)>],
            index: Vec<Option<usize>>,
            low: Vec<usize>,
            stack: Vec<usize>,
            on_stack: Vec<bool>,
            component: Vec<usize>,
            next_index: usize,
            next_component: usize,
        }
        impl Tarjan<'_> {
            fn visit(&mut self, v: usize) {
                self.index[v] = Some(self.next_index);
                self.low[v] = self.next_index;
                self.next_index += 1;
                self.stack.push(v);
                self.on_stack[v] = true;
                let edges = self.edges;
                for &w in edges[v].keys() {
                    match self.index[w] {
                        None => {
                            self.visit(w);
                            self.low[v] = self.low[v].min(self.low[w]);
                        }
                        Some(index) if self.on_stack[w] => self.low[v] = self.low[v].min(index),
                        Some(_) => {}
                    }
                }
                if Some(self.low[v]) == self.index[v] {
                    while let Some(w) = self.stack.pop() {
                        self.on_stack[w] = false;
                        self.component[w] = self.next_component;
                        if w == v {
                            break;
                        }
                    }
                    self.next_component += 1;
                }
            }
        }
        let n = self.files.len();
        let mut tarjan = Tarjan {
            edges: &self.edges,
            index: vec![None; n],
            low: vec![0; n],
            stack: Vec::new(),
            on_stack: vec![false; n],
            component: vec![0; n],
            next_index: 0,
            next_component: 0,
        };
        for v in 0..n {
            if tarjan.index[v].is_none() {
                tarjan.visit(v);
            }
        }
        tarjan.component
    }

    /// The cycles, the modules caught in them and the imports that close them; empty when there
    /// is no cycle.
    fn cycle_report(&self) -> String {
        let cycles = self.cycles();
        if cycles.is_empty() {
            return String::new();
        }
        let mut out = String::new();
        let component = self.components();
        let mut groups: BTreeMap<usize, Vec<&str>> = BTreeMap::new();
        for (id, file) in self.files.iter().enumerate() {
            groups.entry(component[id]).or_default().push(file);
        }
        for files in groups.values().filter(|files| files.len() > 1) {
            let _ = writeln!(out, "modules in one cycle group: {}", files.join(", "));
        }
        let listed = cycles.len().min(MAX_CYCLES_LISTED);
        let _ = writeln!(out, "cycles ({listed} listed):");
        let mut on_cycles = BTreeSet::new();
        for cycle in &cycles[..listed] {
            let names: Vec<&str> = cycle.iter().map(|&id| self.files[id].as_str()).collect();
            let _ = writeln!(out, "  {} -> {}", names.join(" -> "), names[0]);
            for (i, &from) in cycle.iter().enumerate() {
                on_cycles.insert((from, cycle[(i + 1) % cycle.len()]));
            }
        }
        if cycles.len() > MAX_CYCLES_LISTED {
            let _ = writeln!(
                out,
                "  ... and more (the list stops at {MAX_CYCLES_LISTED})"
            );
        }
        let _ = writeln!(out, "imports on those cycles (the first line of each):");
        for (from, to) in on_cycles {
            let (line, path) = &self.edges[from][&to];
            let _ = writeln!(
                out,
                "  {}:{line} `{path}` -> {}",
                self.files[from], self.files[to]
            );
        }
        out
    }
}

/// A path found in a file's code.
#[derive(Clone, Debug, PartialEq)]
struct Reference {
    /// The inline modules (`mod name { ... }`) the path is written in, outermost first.
    scope: Vec<String>,
    /// The path's segments; a `use` glob or `self` leaf ends at its prefix.
    segments: Vec<String>,
    /// 1-based line.
    line: usize,
}

/// What one file declares and names.
#[derive(Debug, Default)]
struct Scan {
    /// `(scope, name)` of every `mod name;` and `mod name { ... }`.
    declared: BTreeSet<(Vec<String>, String)>,
    /// Every path that may name a module of the crate.
    references: Vec<Reference>,
}

/// The module file a reference names, if it names one of the crate's modules.
fn resolve(
    file_module: &[String],
    reference: &Reference,
    declared: &BTreeSet<(Vec<String>, String)>,
    modules: &BTreeMap<Vec<String>, usize>,
) -> Option<usize> {
    let mut base: Vec<String> = file_module.to_vec();
    base.extend(reference.scope.iter().cloned());
    let segments = &reference.segments;
    let first = segments.first()?;
    let mut rest = 1;
    match first.as_str() {
        "crate" => base.clear(),
        "self" | "super" => {
            rest = 0;
            while let Some(segment) = segments.get(rest) {
                match segment.as_str() {
                    "self" => {}
                    "super" => {
                        base.pop()?;
                    }
                    _ => break,
                }
                rest += 1;
            }
        }
        name if declared.contains(&(reference.scope.clone(), name.to_owned())) => {
            base.push(name.to_owned());
        }
        _ => return None,
    }
    for segment in &segments[rest..] {
        base.push(segment.clone());
        if !modules.contains_key(&base) {
            base.pop();
            break;
        }
    }
    // The deepest module file: an inline module belongs to the file that holds it.
    loop {
        if let Some(&id) = modules.get(&base) {
            return Some(id);
        }
        base.pop()?;
    }
}

/// The source with comments and string and character literals blanked out (line breaks kept).
fn strip(source: &str) -> String {
    let chars: Vec<char> = source.chars().collect();
    let mut out = String::with_capacity(source.len());
    let blank = |out: &mut String, c: char| out.push(if c == '\n' { '\n' } else { ' ' });
    let is_ident = |c: char| c.is_alphanumeric() || c == '_';
    let mut i = 0;
    while i < chars.len() {
        let c = chars[i];
        let next = chars.get(i + 1).copied();
        let starts_token = i == 0 || !is_ident(chars[i - 1]);
        if c == '/' && next == Some('/') {
            while i < chars.len() && chars[i] != '\n' {
                i += 1;
            }
        } else if c == '/' && next == Some('*') {
            let mut depth = 0;
            while i < chars.len() {
                if chars[i] == '/' && chars.get(i + 1) == Some(&'*') {
                    depth += 1;
                    out.push_str("  ");
                    i += 2;
                } else if chars[i] == '*' && chars.get(i + 1) == Some(&'/') {
                    depth -= 1;
                    out.push_str("  ");
                    i += 2;
                    if depth == 0 {
                        break;
                    }
                } else {
                    blank(&mut out, chars[i]);
                    i += 1;
                }
            }
        } else if let Some(end) = starts_token.then(|| raw_string_end(&chars, i)).flatten() {
            while i < end {
                blank(&mut out, chars[i]);
                i += 1;
            }
        } else if c == '"' || (starts_token && matches!(c, 'b' | 'c') && next == Some('"')) {
            if c != '"' {
                out.push(' ');
                i += 1;
            }
            out.push(' ');
            i += 1;
            while i < chars.len() && chars[i] != '"' {
                if chars[i] == '\\' {
                    out.push(' ');
                    i += 1;
                }
                if let Some(&c) = chars.get(i) {
                    blank(&mut out, c);
                }
                i += 1;
            }
            out.push(' ');
            i += 1;
        } else if c == '\'' && next == Some('\\') {
            // An escaped character literal: '\n', '\'', '\u{1F600}'.
            out.push_str("   ");
            i += 3;
            while i < chars.len() && chars[i] != '\'' {
                i += 1;
                out.push(' ');
            }
            out.push(' ');
            i += 1;
        } else if c == '\'' && chars.get(i + 2) == Some(&'\'') {
            // A character literal 'x' (a lifetime 'a is never followed by a quote).
            out.push_str("   ");
            i += 3;
        } else {
            out.push(c);
            i += 1;
        }
    }
    out
}

/// The end (exclusive) of a raw string literal (`r"..."`, `r#"..."#`, `br"..."`, `cr"..."`)
/// starting at `i`, if one starts there.
fn raw_string_end(chars: &[char], mut i: usize) -> Option<usize> {
    if matches!(chars.get(i), Some('b' | 'c')) {
        i += 1;
    }
    if chars.get(i) != Some(&'r') {
        return None;
    }
    i += 1;
    let mut hashes = 0;
    while chars.get(i) == Some(&'#') {
        hashes += 1;
        i += 1;
    }
    if chars.get(i) != Some(&'"') {
        return None;
    }
    i += 1;
    while i < chars.len() {
        if chars[i] == '"' && (1..=hashes).all(|k| chars.get(i + k) == Some(&'#')) {
            return Some(i + 1 + hashes);
        }
        i += 1;
    }
    Some(chars.len())
}

/// A token of stripped source: an identifier or keyword, `::`, or one other character.
#[derive(Clone, Debug, PartialEq)]
struct Token {
    text: String,
    line: usize,
}

fn tokenize(stripped: &str) -> Vec<Token> {
    let chars: Vec<char> = stripped.chars().collect();
    let mut tokens = Vec::new();
    let mut line = 1;
    let mut i = 0;
    while i < chars.len() {
        let c = chars[i];
        if c == '\n' {
            line += 1;
            i += 1;
        } else if c.is_whitespace() {
            i += 1;
        } else if c.is_alphanumeric() || c == '_' {
            let start = i;
            while i < chars.len() && (chars[i].is_alphanumeric() || chars[i] == '_') {
                i += 1;
            }
            let text: String = chars[start..i].iter().collect();
            if text == "r" && chars.get(i) == Some(&'#') {
                // A raw identifier `r#name` is the identifier `name`.
                i += 1;
            } else if !c.is_ascii_digit() {
                tokens.push(Token { text, line });
            }
        } else if c == ':' && chars.get(i + 1) == Some(&':') {
            tokens.push(Token {
                text: "::".into(),
                line,
            });
            i += 2;
        } else {
            tokens.push(Token {
                text: c.to_string(),
                line,
            });
            i += 1;
        }
    }
    tokens
}

/// The declarations and paths of one file.
fn scan(source: &str) -> Scan {
    let tokens = tokenize(&strip(source));
    let text = |i: usize| tokens.get(i).map_or("", |t| t.text.as_str());
    let is_ident = |i: usize| {
        text(i)
            .chars()
            .next()
            .is_some_and(|c| c.is_alphabetic() || c == '_')
    };
    let mut out = Scan::default();
    // Inline modules around the cursor, with the brace depth inside each.
    let mut scope: Vec<(String, usize)> = Vec::new();
    let mut depth = 0;
    let mut i = 0;
    while i < tokens.len() {
        let names = || {
            scope
                .iter()
                .map(|(name, _)| name.clone())
                .collect::<Vec<_>>()
        };
        match text(i) {
            "#" if text(i + 1) == "[" && is_cfg_test(&tokens, i + 2) => {
                i = skip_test_module(&tokens, i);
            }
            "pub" if text(i + 1) == "(" => {
                // `pub(crate)`, `pub(super)`, `pub(in path)` restrict visibility; no import.
                i = matching(&tokens, i + 1) + 1;
            }
            "mod" if is_ident(i + 1) && matches!(text(i + 2), ";" | "{") => {
                out.declared.insert((names(), text(i + 1).to_owned()));
                if text(i + 2) == "{" {
                    depth += 1;
                    scope.push((text(i + 1).to_owned(), depth));
                }
                i += 3;
            }
            "use" => {
                let line = tokens[i].line;
                let mut paths = Vec::new();
                i = parse_use_tree(&tokens, i + 1, Vec::new(), &mut paths);
                while i < tokens.len() && text(i) != ";" {
                    i += 1;
                }
                let scope = names();
                out.references
                    .extend(paths.into_iter().map(|segments| Reference {
                        scope: scope.clone(),
                        segments,
                        line,
                    }));
                i += 1;
            }
            "{" => {
                depth += 1;
                i += 1;
            }
            "}" => {
                if scope.last().is_some_and(|(_, d)| *d == depth) {
                    scope.pop();
                }
                depth = depth.saturating_sub(1);
                i += 1;
            }
            _ if is_ident(i)
                && text(i + 1) == "::"
                && is_ident(i + 2)
                && !matches!(text(i.wrapping_sub(1)), "::" | ".") =>
            {
                let line = tokens[i].line;
                let mut segments = vec![text(i).to_owned()];
                i += 1;
                while text(i) == "::" && is_ident(i + 1) {
                    segments.push(text(i + 1).to_owned());
                    i += 2;
                }
                out.references.push(Reference {
                    scope: names(),
                    segments,
                    line,
                });
            }
            _ => i += 1,
        }
    }
    out
}

/// Whether the tokens from `i` are `cfg(test)]`.
fn is_cfg_test(tokens: &[Token], i: usize) -> bool {
    let expected = ["cfg", "(", "test", ")", "]"];
    expected
        .iter()
        .enumerate()
        .all(|(k, e)| tokens.get(i + k).is_some_and(|t| t.text == *e))
}

/// After `#[cfg(test)]` at `i`: past the `mod name { ... }` block it marks, or just past the
/// attribute when it marks something else.
fn skip_test_module(tokens: &[Token], i: usize) -> usize {
    let after_attribute = i + 7;
    let mut j = after_attribute;
    let text = |j: usize| tokens.get(j).map_or("", |t| t.text.as_str());
    // Further attributes and a visibility may sit between the attribute and `mod`.
    loop {
        if (text(j) == "#" && text(j + 1) == "[") || (text(j) == "pub" && text(j + 1) == "(") {
            j = matching(tokens, j + 1) + 1;
        } else if text(j) == "pub" {
            j += 1;
        } else {
            break;
        }
    }
    if text(j) == "mod" && text(j + 2) == "{" {
        matching(tokens, j + 2) + 1
    } else {
        after_attribute
    }
}

/// The index of the bracket closing the one at `open`, or the end of the tokens.
fn matching(tokens: &[Token], open: usize) -> usize {
    let (opening, closing) = match tokens[open].text.as_str() {
        "(" => ("(", ")"),
        "[" => ("[", "]"),
        _ => ("{", "}"),
    };
    let mut depth = 0;
    for (j, token) in tokens.iter().enumerate().skip(open) {
        if token.text == opening {
            depth += 1;
        } else if token.text == closing {
            depth -= 1;
            if depth == 0 {
                return j;
            }
        }
    }
    tokens.len()
}

/// Parses a use tree from `i` with the segments of the enclosing groups in `prefix`, pushing every
/// full path it names (a glob or a `self` leaf names its prefix); returns the index after it.
fn parse_use_tree(
    tokens: &[Token],
    mut i: usize,
    mut prefix: Vec<String>,
    out: &mut Vec<Vec<String>>,
) -> usize {
    let text = |i: usize| tokens.get(i).map_or("", |t| t.text.as_str());
    if text(i) == "::" {
        // `use ::name::...`: an external crate.
        prefix.push("::".into());
        i += 1;
    }
    loop {
        match text(i) {
            "{" => {
                i += 1;
                while i < tokens.len() && !matches!(text(i), "}" | ";") {
                    i = parse_use_tree(tokens, i, prefix.clone(), out);
                    if text(i) == "," {
                        i += 1;
                    }
                }
                return i + 1;
            }
            "*" => {
                out.push(prefix);
                return i + 1;
            }
            "self" if !prefix.is_empty() => {
                if text(i + 1) == "::" {
                    prefix.push("self".into());
                    i += 2;
                    continue;
                }
                out.push(prefix);
                return skip_rename(tokens, i + 1);
            }
            segment if segment.starts_with(|c: char| c.is_alphabetic() || c == '_') => {
                prefix.push(segment.to_owned());
                if text(i + 1) == "::" {
                    i += 2;
                } else {
                    out.push(prefix);
                    return skip_rename(tokens, i + 1);
                }
            }
            _ => return i,
        }
    }
}

/// Past an optional `as name`.
fn skip_rename(tokens: &[Token], i: usize) -> usize {
    if tokens.get(i).is_some_and(|t| t.text == "as") {
        i + 2
    } else {
        i
    }
}

// The parser's tests, on small strings.

fn paths(source: &str) -> Vec<String> {
    scan(source)
        .references
        .iter()
        .map(|r| r.segments.join("::"))
        .collect()
}

fn graph(files: &[(&str, &str)]) -> ImportGraph {
    let sources: Vec<(String, String)> = files
        .iter()
        .map(|(path, text)| (path.to_string(), text.to_string()))
        .collect();
    ImportGraph::build(&sources)
}

fn edges(g: &ImportGraph) -> Vec<(String, String)> {
    let mut out = Vec::new();
    for (from, targets) in g.edges.iter().enumerate() {
        for to in targets.keys() {
            out.push((g.files[from].clone(), g.files[*to].clone()));
        }
    }
    out
}

fn edge(from: &str, to: &str) -> (String, String) {
    (from.to_owned(), to.to_owned())
}

#[test]
fn parser_detects_a_cycle_through_three_modules() {
    let g = graph(&[
        ("lib.rs", "mod a; mod b; mod c;"),
        ("a.rs", "use crate::b::B;"),
        ("b.rs", "fn f() { crate::c::g(); }"),
        ("c/mod.rs", "use super::a::*;"),
    ]);
    let cycles: Vec<Vec<&str>> = g
        .cycles()
        .iter()
        .map(|c| c.iter().map(|&id| g.files[id].as_str()).collect())
        .collect();
    assert_eq!(cycles, [["a.rs", "b.rs", "c/mod.rs"]]);
    let report = g.cycle_report();
    assert!(
        report.contains("a.rs -> b.rs -> c/mod.rs -> a.rs"),
        "{report}"
    );
    assert!(
        report.contains("b.rs:1 `crate::c::g` -> c/mod.rs"),
        "{report}"
    );
}

#[test]
fn parser_finds_every_cycle_and_none_in_a_tree() {
    let g = graph(&[
        (
            "lib.rs",
            "mod a; mod b; pub struct Root; fn f() { a::f(); }",
        ),
        ("a.rs", "use crate::Root; use crate::b;"),
        ("b.rs", "use crate::a::X;"),
    ]);
    let cycles = g.cycles();
    // a.rs <-> b.rs and a.rs <-> lib.rs.
    assert_eq!(
        cycles,
        [vec![0, 1], vec![0, 2]],
        "{:?} {:?}",
        g.files,
        edges(&g)
    );
    let tree = graph(&[
        ("lib.rs", "mod a; mod b; use b::B;"),
        ("a.rs", "pub struct A;"),
        ("b.rs", "use crate::a::A; pub struct B(A);"),
    ]);
    assert!(tree.cycles().is_empty());
    assert!(tree.cycle_report().is_empty());
}

#[test]
fn parser_a_mod_declaration_alone_is_not_an_import() {
    let g = graph(&[
        ("main.rs", "mod a;\npub mod b;\nfn main() {}"),
        ("a.rs", "use crate::b::B;"),
        ("b.rs", "use super::a;"),
    ]);
    assert_eq!(edges(&g), [edge("a.rs", "b.rs"), edge("b.rs", "a.rs")]);
}

#[test]
fn parser_ignores_comments_and_string_literals() {
    let source = r####"
        // use crate::a::A;
        /* crate::b::B /* nested */ crate::c::C */
        /// Calls [`crate::d::D`]: `crate::d::f()`.
        const S: &str = "crate::e::E \" crate::f::F";
        const R: &str = r#"crate::g::G " still a string"#;
        const B: &[u8] = b"crate::h::H";
        const C: char = '"'; const Q: char = '\''; fn f<'a>(x: &'a str) {}
        use crate::real::Item;
    "####;
    assert_eq!(paths(source), ["crate::real::Item"]);
    assert_eq!(scan(source).references[0].line, 9);
}

#[test]
fn parser_skips_test_modules_only() {
    let source = "
        fn f() {}
        #[cfg(test)]
        mod tests {
            use super::*;
            use crate::other::X;
            fn g() { crate::more::y() }
        }
        mod inner { use super::*; }
        use crate::after::Z;
    ";
    assert_eq!(paths(source), ["super", "crate::after::Z"]);
    assert_eq!(scan(source).references[0].scope, ["inner"]);
}

#[test]
fn parser_expands_use_groups() {
    let source = "
        pub use crate::{a::X, b::{self, c::{Y, Z as W}, *}, d};
        use super::{self as parent, super::e::F};
        use ::std::fmt; use std::io;
    ";
    assert_eq!(
        paths(source),
        [
            "crate::a::X",
            "crate::b",
            "crate::b::c::Y",
            "crate::b::c::Z",
            "crate::b",
            "crate::d",
            "super",
            "super::super::e::F",
            "::::std::fmt",
            "std::io",
        ]
    );
}

#[test]
fn parser_resolves_paths_to_the_deepest_module_file() {
    let g = graph(&[
        (
            "lib.rs",
            "pub mod api; pub mod render; pub enum SphSystems {}",
        ),
        ("api.rs", "pub struct SphParams;"),
        (
            "render/mod.rs",
            "pub mod stages; pub mod buffers; use buffers::X; pub struct SphRun;",
        ),
        (
            "render/buffers.rs",
            "pub struct X; pub mod slot { use super::X; }",
        ),
        (
            "render/stages/mod.rs",
            "pub mod count_cells; pub mod density;",
        ),
        ("render/stages/count_cells.rs", "pub struct C;"),
        (
            "render/stages/density.rs",
            "use super::SphRun; fn f(p: crate::api::SphParams) { \
             let _ = crate::render::stages::count_cells::C; crate::SphSystems::go(); \
             bevy::render::buffers::Y; Self::z(); self::q(); }",
        ),
    ]);
    assert_eq!(
        edges(&g),
        [
            edge("render/mod.rs", "render/buffers.rs"),
            edge("render/stages/density.rs", "api.rs"),
            edge("render/stages/density.rs", "lib.rs"),
            edge("render/stages/density.rs", "render/stages/count_cells.rs"),
            edge("render/stages/density.rs", "render/stages/mod.rs"),
        ]
    );
}

#[test]
fn parser_follows_bare_paths_of_declared_children_only() {
    let g = graph(&[
        (
            "lib.rs",
            "mod stages; mod buffers; fn f(app: &mut App) { stages::embed_shaders(app); } \
             use buffers::X; fn g() { other::h(); Vec::<u8>::new(); x.iter::<u8>(); }",
        ),
        ("stages.rs", "pub fn embed_shaders() {}"),
        ("buffers.rs", "pub struct X;"),
        ("other.rs", "pub fn h() {}"),
    ]);
    assert_eq!(
        edges(&g),
        [edge("lib.rs", "buffers.rs"), edge("lib.rs", "stages.rs")]
    );
}

#[test]
fn parser_ignores_visibility_restrictions() {
    assert_eq!(
        paths("pub(crate) fn a() {} pub(super) fn b() {} pub(in crate::x) fn c() {}"),
        Vec::<String>::new()
    );
}
