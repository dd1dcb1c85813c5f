//! The check that a crate's top-level modules form no cycle. Included by both crates' test
//! binaries (`tests/main.rs`, `physics/tests/main.rs`).
//!
//! Each source file of a crate belongs to the top-level module its path starts with
//! (`src/solver/boundary/joint.rs` to `solver`). Its paths that leave that module are
//! `crate::X…`, `use crate::{X, …}` and `super::…` climbing past it; each is an edge from the
//! file's top-level module to `X` (or to the module a name re-exported by the crate root comes
//! from: `pub use interface::law;` makes `crate::law` an edge to `interface`). Comments, strings
//! and char literals are skipped; `mod NAME { … }` blocks inside a file count in `super::`.
//! Names that are not modules of the crate (re-exports of another crate) make no edge. Test
//! code is no layer: an item under `#[cfg(test)]` (a `mod tests { … }`, a `mod tests;` and its
//! file) makes no edge, so a unit test may build its fixture with any module (the default of
//! `cargo modules dependencies`, which leaves `cfg(test)` out too).

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

/// One path from a top-level module to another: where it is and how it reads.
#[derive(Clone, Debug)]
pub struct Edge {
    pub from: String,
    pub to: String,
    /// `file:line`, the file relative to the crate's folder.
    pub at: String,
    /// The path as written, up to the first name past the crate root (`crate::solver`).
    pub path: String,
}

#[derive(Clone, Debug, PartialEq)]
enum Tok {
    Ident(String),
    /// `::`
    Sep,
    Open,
    Close,
    Comma,
    Semi,
    Star,
    /// `$` (of `$crate`), or any other character.
    Other(char),
}

/// The tokens of a Rust source that paths are made of, each with its line; comments, strings,
/// char literals, lifetimes and numbers are dropped.
fn tokens(src: &str) -> Vec<(Tok, usize)> {
    let c: Vec<char> = src.chars().collect();
    let mut out = Vec::new();
    let (mut i, mut line) = (0, 1);
    let at = |i: usize| c.get(i).copied().unwrap_or('\0');
    while i < c.len() {
        let ch = c[i];
        if ch == '\n' {
            line += 1;
            i += 1;
        } else if ch.is_whitespace() {
            i += 1;
        } else if ch == '/' && at(i + 1) == '/' {
            while i < c.len() && c[i] != '\n' {
                i += 1;
            }
        } else if ch == '/' && at(i + 1) == '*' {
            let mut depth = 0;
            loop {
                if i >= c.len() {
                    break;
                }
                if c[i] == '/' && at(i + 1) == '*' {
                    depth += 1;
                    i += 2;
                } else if c[i] == '*' && at(i + 1) == '/' {
                    depth -= 1;
                    i += 2;
                    if depth == 0 {
                        break;
                    }
                } else {
                    line += usize::from(c[i] == '\n');
                    i += 1;
                }
            }
        } else if ch == '"' || ((ch == 'b' || ch == 'c') && at(i + 1) == '"') {
            i += if ch == '"' { 1 } else { 2 };
            while i < c.len() && c[i] != '"' {
                if c[i] == '\\' {
                    i += 1;
                }
                line += usize::from(at(i) == '\n');
                i += 1;
            }
            i += 1;
        } else if (ch == 'r' && matches!(at(i + 1), '"' | '#'))
            || ((ch == 'b' || ch == 'c') && at(i + 1) == 'r' && matches!(at(i + 2), '"' | '#'))
        {
            // A raw string: r"…", r#"…"#, br"…", cr#"…"#.
            i += if ch == 'r' { 1 } else { 2 };
            let mut hashes = 0;
            while at(i) == '#' {
                hashes += 1;
                i += 1;
            }
            if at(i) != '"' {
                // `r#ident`, a raw identifier.
                let start = i;
                while i < c.len() && (c[i].is_alphanumeric() || c[i] == '_') {
                    i += 1;
                }
                out.push((Tok::Ident(c[start..i].iter().collect()), line));
                continue;
            }
            i += 1;
            loop {
                if i >= c.len() {
                    break;
                }
                if c[i] == '"' && (1..=hashes).all(|k| at(i + k) == '#') {
                    i += 1 + hashes;
                    break;
                }
                line += usize::from(c[i] == '\n');
                i += 1;
            }
        } else if ch == '\'' {
            // A char literal ('a', '\n', '\u{2192}') or a lifetime ('a).
            if at(i + 1) == '\\' {
                i += 2;
                while i < c.len() && c[i] != '\'' {
                    i += 1;
                }
                i += 1;
            } else if at(i + 2) == '\'' {
                i += 3;
            } else {
                i += 1;
                while i < c.len() && (c[i].is_alphanumeric() || c[i] == '_') {
                    i += 1;
                }
            }
        } else if ch.is_alphabetic() || ch == '_' {
            let start = i;
            while i < c.len() && (c[i].is_alphanumeric() || c[i] == '_') {
                i += 1;
            }
            out.push((Tok::Ident(c[start..i].iter().collect()), line));
        } else if ch.is_ascii_digit() {
            while i < c.len() && (c[i].is_alphanumeric() || c[i] == '_') {
                i += 1;
            }
        } else {
            let tok = match ch {
                ':' if at(i + 1) == ':' => {
                    i += 1;
                    Tok::Sep
                }
                '{' => Tok::Open,
                '}' => Tok::Close,
                ',' => Tok::Comma,
                ';' => Tok::Semi,
                '*' => Tok::Star,
                other => Tok::Other(other),
            };
            out.push((tok, line));
            i += 1;
        }
    }
    out
}

fn ident(t: Option<&(Tok, usize)>) -> Option<&str> {
    match t {
        Some((Tok::Ident(s), _)) => Some(s),
        _ => None,
    }
}

/// The first name of each item of the `{ … }` group opening at `toks[open]`, `self` left out.
fn group_heads(toks: &[(Tok, usize)], open: usize) -> Vec<String> {
    let (mut depth, mut heads, mut expect) = (0, Vec::new(), true);
    for (t, _) in &toks[open..] {
        match t {
            Tok::Open => {
                depth += 1;
                expect = depth == 1;
            }
            Tok::Close => {
                depth -= 1;
                if depth == 0 {
                    break;
                }
            }
            Tok::Comma if depth == 1 => expect = true,
            Tok::Ident(s) if expect && depth == 1 => {
                expect = false;
                if s != "self" {
                    heads.push(s.clone());
                }
            }
            _ if depth == 1 => expect = false,
            _ => {}
        }
    }
    heads
}

/// Whether `toks[k..]` starts with `#[cfg(test)]` (or `#![cfg(test)]`), and where it ends.
fn cfg_test(toks: &[(Tok, usize)], k: usize) -> Option<usize> {
    let mut j = k;
    if toks.get(j)?.0 != Tok::Other('#') {
        return None;
    }
    j += 1;
    if toks.get(j)?.0 == Tok::Other('!') {
        j += 1;
    }
    let want = [
        Tok::Other('['),
        Tok::Ident("cfg".into()),
        Tok::Other('('),
        Tok::Ident("test".into()),
        Tok::Other(')'),
        Tok::Other(']'),
    ];
    for w in want {
        if toks.get(j)?.0 != w {
            return None;
        }
        j += 1;
    }
    Some(j)
}

/// The end of the item that starts at `toks[k]`: past its `;` or its closing `}` (and a `;`
/// right after it).
fn item_end(toks: &[(Tok, usize)], k: usize) -> usize {
    let (mut j, mut depth) = (k, 0);
    while j < toks.len() {
        match toks[j].0 {
            Tok::Semi if depth == 0 => return j + 1,
            Tok::Open => depth += 1,
            Tok::Close => {
                depth -= 1;
                if depth == 0 {
                    let next = j + 1;
                    return next + usize::from(toks.get(next).is_some_and(|t| t.0 == Tok::Semi));
                }
            }
            _ => {}
        }
        j += 1;
    }
    j
}

/// The `.rs` files under `dir`, sorted.
fn rust_files(dir: &Path) -> Vec<PathBuf> {
    let mut files = Vec::new();
    for entry in std::fs::read_dir(dir).unwrap() {
        let path = entry.unwrap().path();
        if path.is_dir() {
            files.extend(rust_files(&path));
        } else if path.extension().is_some_and(|e| e == "rs") {
            files.push(path);
        }
    }
    files.sort();
    files
}

/// The top-level modules of the crate whose root is `root` (`mod NAME;` and `mod NAME { … }` at
/// its top level), and what its `use` lines re-export from them (`pub use interface::law;`:
/// `law` → `interface`).
fn root_modules(root: &Path) -> (BTreeSet<String>, BTreeMap<String, String>) {
    let toks = tokens(&std::fs::read_to_string(root).unwrap());
    let (mut modules, mut uses, mut depth) = (BTreeSet::new(), Vec::new(), 0);
    for (k, (t, _)) in toks.iter().enumerate() {
        match t {
            Tok::Open => depth += 1,
            Tok::Close => depth -= 1,
            Tok::Ident(s) if depth == 0 && s == "mod" => {
                modules.insert(ident(toks.get(k + 1)).unwrap().to_string());
            }
            Tok::Ident(s) if depth == 0 && s == "use" => uses.push(k + 1),
            _ => {}
        }
    }
    let mut aliases = BTreeMap::new();
    for start in uses {
        let Some(first) = ident(toks.get(start)) else {
            continue;
        };
        if !modules.contains(first) {
            continue;
        }
        // The last name of `use first::a::b;` or each head of `use first::{a, b};`.
        let mut k = start;
        while toks[k].0 != Tok::Semi && toks[k].0 != Tok::Open {
            k += 1;
        }
        let names = if toks[k].0 == Tok::Open {
            group_heads(&toks, k)
        } else {
            vec![ident(toks.get(k - 1)).unwrap().to_string()]
        };
        for name in names {
            aliases.insert(name, first.to_string());
        }
    }
    (modules, aliases)
}

/// The module path of a source file: `solver/boundary/mod.rs` → [solver, boundary].
fn module_path(rel: &Path) -> Vec<String> {
    let mut path: Vec<String> = rel
        .with_extension("")
        .iter()
        .map(|p| p.to_str().unwrap().to_string())
        .collect();
    if path.last().is_some_and(|p| p == "mod") {
        path.pop();
    }
    path
}

/// What one file says: the paths that leave its top-level module (`top` maps a name to its
/// top-level module, `None` for a name of another crate), and the modules it declares under
/// `#[cfg(test)]` with a file of their own (`mod tests;`).
struct FileScan {
    /// (top-level module, line, path as written).
    paths: Vec<(String, usize, String)>,
    test_modules: Vec<Vec<String>>,
}

fn scan_file(
    toks: &[(Tok, usize)],
    path: &[String],
    top: &dyn Fn(&str) -> Option<String>,
) -> FileScan {
    let mut scan = FileScan {
        paths: Vec::new(),
        test_modules: Vec::new(),
    };
    // Inline `mod NAME {` blocks open at the brace depths kept here.
    let (mut inline, mut depth): (Vec<(String, usize)>, usize) = (Vec::new(), 0);
    let here = |inline: &[(String, usize)]| {
        let mut m = path.to_vec();
        m.extend(inline.iter().map(|(n, _)| n.clone()));
        m
    };
    let mut k = 0;
    while k < toks.len() {
        if let Some(after) = cfg_test(toks, k) {
            if toks[k + 1].0 == Tok::Other('!') {
                // `#![cfg(test)]`: the whole file (or block) is test code.
                return FileScan {
                    paths: Vec::new(),
                    test_modules: Vec::new(),
                };
            }
            let end = item_end(toks, after);
            // `#[cfg(test)] mod NAME;` (possibly after more attributes): its file is test code.
            if toks[end - 1].0 == Tok::Semi {
                if let Some(m) = (after..end).find(|&j| ident(toks.get(j)) == Some("mod")) {
                    if let Some(name) = ident(toks.get(m + 1)) {
                        let mut module = here(&inline);
                        module.push(name.to_string());
                        scan.test_modules.push(module);
                    }
                }
            }
            k = end;
            continue;
        }
        let (t, line) = &toks[k];
        match t {
            Tok::Open => depth += 1,
            Tok::Close => {
                if inline.last().is_some_and(|(_, d)| *d == depth) {
                    inline.pop();
                }
                depth -= 1;
            }
            Tok::Ident(s)
                if s == "mod"
                    && ident(toks.get(k + 1)).is_some()
                    && toks.get(k + 2).is_some_and(|t| t.0 == Tok::Open) =>
            {
                inline.push((ident(toks.get(k + 1)).unwrap().to_string(), depth + 1));
            }
            Tok::Ident(s)
                if s == "crate"
                    && !(k > 0 && toks[k - 1].0 == Tok::Other('$'))
                    && toks.get(k + 1).is_some_and(|t| t.0 == Tok::Sep) =>
            {
                if let Some(name) = ident(toks.get(k + 2)) {
                    if let Some(to) = top(name) {
                        scan.paths.push((to, *line, format!("crate::{name}")));
                    }
                } else if toks.get(k + 2).is_some_and(|t| t.0 == Tok::Open) {
                    for name in group_heads(toks, k + 2) {
                        if let Some(to) = top(&name) {
                            scan.paths.push((to, *line, format!("crate::{{{name}}}")));
                        }
                    }
                }
            }
            Tok::Ident(s)
                if s == "super"
                    && !(k > 0 && toks[k - 1].0 == Tok::Sep)
                    && toks.get(k + 1).is_some_and(|t| t.0 == Tok::Sep) =>
            {
                let mut ups = 0;
                let mut j = k;
                while ident(toks.get(j)) == Some("super")
                    && toks.get(j + 1).is_some_and(|t| t.0 == Tok::Sep)
                {
                    ups += 1;
                    j += 2;
                }
                let mut module = here(&inline);
                assert!(
                    ups <= module.len(),
                    "{path:?}:{line}: super:: above the crate root"
                );
                module.truncate(module.len() - ups);
                let written = format!(
                    "{}{}",
                    "super::".repeat(ups),
                    ident(toks.get(j)).unwrap_or("")
                );
                if let Some(first) = module.first() {
                    if let Some(to) = top(first) {
                        scan.paths.push((to, *line, written));
                    }
                } else if let Some(name) = ident(toks.get(j)) {
                    if let Some(to) = top(name) {
                        scan.paths.push((to, *line, written));
                    }
                } else if toks.get(j).is_some_and(|t| t.0 == Tok::Open) {
                    for name in group_heads(toks, j) {
                        if let Some(to) = top(&name) {
                            scan.paths.push((to, *line, format!("{written}{{{name}}}")));
                        }
                    }
                }
                k = j;
                continue;
            }
            _ => {}
        }
        k += 1;
    }
    scan
}

/// Every path of the crate rooted at `crate_dir/src/<root_file>` that goes from one of its
/// top-level modules to another, in file order.
pub fn module_edges(crate_dir: &Path, root_file: &str) -> Vec<Edge> {
    let src = crate_dir.join("src");
    let (modules, aliases) = root_modules(&src.join(root_file));
    let top = |name: &str| -> Option<String> {
        if modules.contains(name) {
            Some(name.to_string())
        } else {
            aliases.get(name).cloned()
        }
    };
    // The crate's files other than its roots and another crate's root, each with its module
    // path, tokens and what it says.
    let mut files = Vec::new();
    for file in rust_files(&src) {
        let path = module_path(file.strip_prefix(&src).unwrap());
        if top(&path[0]).is_none() || (path.len() == 1 && !modules.contains(&path[0])) {
            continue;
        }
        let toks = tokens(&std::fs::read_to_string(&file).unwrap());
        let scan = scan_file(&toks, &path, &top);
        files.push((file, path, scan));
    }
    let test_modules: Vec<Vec<String>> = files
        .iter()
        .flat_map(|(_, _, scan)| scan.test_modules.iter().cloned())
        .collect();
    let mut edges = Vec::new();
    for (file, path, scan) in &files {
        if test_modules.iter().any(|m| path.starts_with(m)) {
            continue;
        }
        let from = top(&path[0]).unwrap();
        let shown = file.strip_prefix(crate_dir).unwrap().display().to_string();
        for (to, line, written) in &scan.paths {
            if *to != from {
                edges.push(Edge {
                    from: from.clone(),
                    to: to.clone(),
                    at: format!("{shown}:{line}"),
                    path: written.clone(),
                });
            }
        }
    }
    edges
}

/// A cycle of the graph of `edges`, as the edges that close it (the first place each is
/// written), or `None`. Found by a depth-first search in name order, so the same sources give
/// the same cycle.
pub fn find_cycle(edges: &[Edge]) -> Option<Vec<Edge>> {
    let mut first: BTreeMap<(&str, &str), &Edge> = BTreeMap::new();
    for e in edges {
        first.entry((&e.from, &e.to)).or_insert(e);
    }
    let mut next: BTreeMap<&str, Vec<&str>> = BTreeMap::new();
    for (from, to) in first.keys() {
        next.entry(from).or_default().push(to);
    }
    // 0 unvisited, 1 on the current path, 2 done.
    let mut state: BTreeMap<&str, u8> = BTreeMap::new();
    fn visit<'a>(
        node: &'a str,
        next: &BTreeMap<&'a str, Vec<&'a str>>,
        state: &mut BTreeMap<&'a str, u8>,
        stack: &mut Vec<&'a str>,
    ) -> Option<Vec<&'a str>> {
        state.insert(node, 1);
        stack.push(node);
        for &to in next.get(node).map(|v| v.as_slice()).unwrap_or(&[]) {
            match state.get(to).copied().unwrap_or(0) {
                1 => {
                    let at = stack.iter().position(|n| *n == to).unwrap();
                    let mut cycle = stack[at..].to_vec();
                    cycle.push(to);
                    return Some(cycle);
                }
                0 => {
                    if let Some(c) = visit(to, next, state, stack) {
                        return Some(c);
                    }
                }
                _ => {}
            }
        }
        stack.pop();
        state.insert(node, 2);
        None
    }
    let nodes: Vec<&str> = next.keys().copied().collect();
    for node in nodes {
        if state.get(node).copied().unwrap_or(0) == 0 {
            if let Some(cycle) = visit(node, &next, &mut state, &mut Vec::new()) {
                return Some(
                    cycle
                        .windows(2)
                        .map(|w| first[&(w[0], w[1])].clone())
                        .collect(),
                );
            }
        }
    }
    None
}

/// `a → b → a` and, one line per edge, where it is written.
pub fn describe(cycle: &[Edge]) -> String {
    let mut s = cycle
        .iter()
        .map(|e| e.from.as_str())
        .chain(cycle.last().map(|e| e.to.as_str()))
        .collect::<Vec<_>>()
        .join(" → ");
    for e in cycle {
        s += &format!("\n  {} → {}: {} ({})", e.from, e.to, e.at, e.path);
    }
    s
}

/// Each top-level module and the top-level modules its paths name, one line each:
/// `solver: energy, interface, mesh`.
pub fn layers(edges: &[Edge]) -> String {
    let mut uses: BTreeMap<&str, BTreeSet<&str>> = BTreeMap::new();
    for e in edges {
        uses.entry(&e.from).or_default().insert(&e.to);
    }
    uses.iter()
        .map(|(from, to)| {
            format!(
                "{from}: {}\n",
                to.iter().copied().collect::<Vec<_>>().join(", ")
            )
        })
        .collect()
}

/// The check of one crate root: `Err` naming the cycle, or a `pending` edge that is gone.
/// `pending` lists the (from, to) edges the check leaves out until they are removed; each
/// must still exist, so that the list shrinks as they go.
pub fn check(crate_dir: &Path, root_file: &str, pending: &[(&str, &str)]) -> Result<(), String> {
    let mut edges = module_edges(crate_dir, root_file);
    for (from, to) in pending {
        if !edges.iter().any(|e| e.from == *from && e.to == *to) {
            return Err(format!(
                "src/{root_file}: {from} no longer uses {to}: remove it from the pending edges"
            ));
        }
    }
    edges.retain(|e| !pending.contains(&(e.from.as_str(), e.to.as_str())));
    match find_cycle(&edges) {
        Some(cycle) => Err(format!(
            "src/{root_file}: module cycle {}\nthe modules and what they use:\n{}",
            describe(&cycle),
            layers(&edges)
        )),
        None => Ok(()),
    }
}
