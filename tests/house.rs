//! The house rules of `src/`, checked so that they stay true: no file over
//! [`MAX_LINES`] lines, and no two sibling modules that use each other, directly or round a
//! longer loop (shared pieces belong one floor down, as `query/context.rs`). A module may
//! use its parent and its children; the rule is about siblings, at every level of the tree.
//!
//! References are read from the source text: `crate::…` and `super::…` paths outside comments,
//! including the groups of a `use` (`super::{a::X, b}`).

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

const MAX_LINES: usize = 900;

/// Every `.rs` file under `dir`, with its module path (`src/query/derivatives/mod.rs` is
/// `["query", "derivatives"]`, `src/lib.rs` is `[]`).
fn modules(root: &Path, dir: &Path, out: &mut Vec<(Vec<String>, PathBuf)>) {
    let mut entries: Vec<_> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .collect();
    entries.sort();
    for p in entries {
        if p.is_dir() {
            modules(root, &p, out);
        } else if p.extension().is_some_and(|e| e == "rs") {
            let rel = p.strip_prefix(root).unwrap();
            let mut path: Vec<String> = rel
                .with_extension("")
                .iter()
                .map(|s| s.to_string_lossy().into_owned())
                .collect();
            if matches!(path.last().map(String::as_str), Some("mod" | "lib")) {
                path.pop();
            }
            out.push((path, p));
        }
    }
}

fn ident(s: &str) -> (&str, &str) {
    let end = s
        .find(|c: char| !(c.is_ascii_alphanumeric() || c == '_'))
        .unwrap_or(s.len());
    (&s[..end], &s[end..])
}

/// The module paths a `crate::`/`super::` reference starting at `rest` (just after the prefix)
/// may lead into: the segments that follow, with a `{…}` group expanded one level.
fn targets(base: &[String], rest: &str, out: &mut Vec<Vec<String>>) {
    let mut path = base.to_vec();
    let mut rest = rest;
    loop {
        if let Some(group) = rest.strip_prefix('{') {
            // Split the group's top level at commas.
            let (mut depth, mut start) = (0, 0);
            for (i, c) in group.char_indices() {
                match c {
                    '{' => depth += 1,
                    '}' if depth == 0 => {
                        targets(&path, group[start..i].trim(), out);
                        return;
                    }
                    '}' => depth -= 1,
                    ',' if depth == 0 => {
                        targets(&path, group[start..i].trim(), out);
                        start = i + 1;
                    }
                    _ => {}
                }
            }
            out.push(path);
            return;
        }
        let (id, after) = ident(rest);
        if id.is_empty() || id.starts_with(|c: char| c.is_ascii_uppercase()) {
            out.push(path);
            return;
        }
        path.push(id.to_string());
        match after.strip_prefix("::") {
            Some(r) => rest = r,
            None => {
                out.push(path);
                return;
            }
        }
    }
}

#[test]
fn no_file_in_src_is_over_the_limit() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let mut files = Vec::new();
    modules(&root, &root, &mut files);
    let too_long: Vec<String> = files
        .iter()
        .filter_map(|(_, p)| {
            let n = std::fs::read_to_string(p).unwrap().lines().count();
            (n > MAX_LINES).then(|| format!("{} ({n} lines)", p.display()))
        })
        .collect();
    assert!(too_long.is_empty(), "over {MAX_LINES} lines: {too_long:?}");
}

#[test]
fn no_two_sibling_modules_use_each_other() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let mut files = Vec::new();
    modules(&root, &root, &mut files);
    let known: BTreeSet<Vec<String>> = files.iter().map(|(m, _)| m.clone()).collect();
    // Edges between siblings: (parent, child a) -> child b.
    let mut edges: BTreeMap<Vec<String>, BTreeSet<(String, String)>> = BTreeMap::new();
    for (module, path) in &files {
        // `super` is the parent module, for `a/b.rs` and `a/b/mod.rs` alike (both are `a::b`).
        let mut refs = Vec::new();
        for line in std::fs::read_to_string(path).unwrap().lines() {
            let code = line.split("//").next().unwrap();
            for (i, _) in code.match_indices("crate::") {
                let before = code[..i].chars().last();
                if before.is_some_and(|c| c.is_ascii_alphanumeric() || c == '_') {
                    continue;
                }
                targets(&[], &code[i + "crate::".len()..], &mut refs);
            }
            for (i, _) in code.match_indices("super::") {
                let before = code[..i].chars().last();
                if before.is_some_and(|c| c.is_ascii_alphanumeric() || c == '_' || c == ':') {
                    continue;
                }
                let mut base = module.clone();
                let mut rest = &code[i..];
                while let Some(r) = rest.strip_prefix("super::") {
                    base.pop();
                    rest = r;
                }
                targets(&base, rest, &mut refs);
            }
        }
        for target in refs {
            // The deepest module the path names.
            let mut t = target;
            while !t.is_empty() && !known.contains(&t) {
                t.pop();
            }
            let common = module.iter().zip(&t).take_while(|(a, b)| a == b).count();
            if common < module.len() && common < t.len() {
                edges
                    .entry(module[..common].to_vec())
                    .or_default()
                    .insert((module[common].clone(), t[common].clone()));
            }
        }
    }
    // A loop among the children of one parent: depth-first search for a back edge.
    let mut loops = Vec::new();
    for (parent, es) in &edges {
        let mut next: BTreeMap<&str, Vec<&str>> = BTreeMap::new();
        for (a, b) in es {
            next.entry(a.as_str()).or_default().push(b.as_str());
        }
        fn visit<'a>(
            n: &'a str,
            next: &BTreeMap<&'a str, Vec<&'a str>>,
            stack: &mut Vec<&'a str>,
            done: &mut BTreeSet<&'a str>,
            loops: &mut Vec<String>,
            parent: &str,
        ) {
            if let Some(pos) = stack.iter().position(|s| *s == n) {
                let mut cycle: Vec<&str> = stack[pos..].to_vec();
                cycle.push(n);
                loops.push(format!("in crate::{}: {}", parent, cycle.join(" -> ")));
                return;
            }
            if !done.insert(n) {
                return;
            }
            stack.push(n);
            for m in next.get(n).into_iter().flatten() {
                visit(m, next, stack, done, loops, parent);
            }
            stack.pop();
        }
        let mut done = BTreeSet::new();
        for start in next.keys() {
            visit(
                start,
                &next,
                &mut Vec::new(),
                &mut done,
                &mut loops,
                &parent.join("::"),
            );
        }
    }
    assert!(loops.is_empty(), "modules that use each other: {loops:#?}");
}
