//! `cargo xtask cycles [CRATE...]`: import cycles between the files of each workspace crate.
//!
//! The graph, per crate target (the library, or `src/main.rs`, and each `src/bin/NAME.rs` or
//! `src/bin/NAME/main.rs` with the files under `src/bin/NAME/`):
//!
//! - A node is a module: a file (`src/a.rs` and `src/a/mod.rs` are module `a`, `src/a/b.rs` is
//!   `a::b`, `lib.rs` and `main.rs` are the crate root) or an inline module in one (`mod tests
//!   { .. }` in `a.rs` is `a::tests`, a child of `a`). So a test module is its own node: it may
//!   use any module (nothing uses it), and a test that drives the API from a lower layer's file
//!   makes no cycle.
//! - An edge A → B is a path in A's code (comments and strings left out) that names module B or
//!   an item in it: `use crate::b::..`, `use super::b::..`, `use self::b::..`, `use b::..` for a
//!   child module `b`, and the same paths written inline (`crate::b::f()`, `$crate::b::..`), use
//!   trees (`use crate::{b::X, c::Y}`) expanded. The path is resolved to the deepest module it
//!   names; an item re-exported elsewhere counts for the module it is named through.
//!   `#[path]` attributes and macro-generated paths are not followed.
//! - A module's references to its own ancestors are not edges: a child module refers to its
//!   parent (`use super::*`) as a matter of course, and every file to the crate root. A
//!   parent's `mod child;` is not an edge either, but its uses of the child's items are. So the
//!   cycles found are between siblings and cousins: `a.rs → b.rs → a.rs`, or `x.rs → a/mod.rs →
//!   a/b.rs → x.rs` through a re-export.
//!
//! Every strongly connected component of more than one file is a cycle: the report gives its
//! files, one cycle through them, and every edge inside it with the line it comes from. The
//! command exits with 1 when any of the crates checked has a cycle.

use std::collections::{BTreeMap, BTreeSet, VecDeque};
use std::path::{Path, PathBuf};

/// A workspace package: its name and its directory relative to the workspace root.
#[derive(Debug, Clone)]
pub struct Package {
    pub name: String,
    pub dir: PathBuf,
}

/// The workspace's packages: the root package (when the root manifest has one) and every
/// `members` entry of `[workspace]`, read from the manifests with plain text matching.
pub fn workspace_packages(root: &Path) -> Result<Vec<Package>, String> {
    let manifest = read(&root.join("Cargo.toml"))?;
    let mut packages = Vec::new();
    if let Some(name) = package_name(&manifest) {
        packages.push(Package {
            name,
            dir: PathBuf::from("."),
        });
    }
    for member in members(&manifest) {
        let text = read(&root.join(&member).join("Cargo.toml"))?;
        let name = package_name(&text).ok_or(format!("{member}/Cargo.toml names no package"))?;
        packages.push(Package {
            name,
            dir: PathBuf::from(member),
        });
    }
    Ok(packages)
}

fn read(path: &Path) -> Result<String, String> {
    std::fs::read_to_string(path).map_err(|e| format!("cannot read {}: {e}", path.display()))
}

/// `name = "..."` in the `[package]` table.
fn package_name(manifest: &str) -> Option<String> {
    let mut in_package = false;
    for line in manifest.lines().map(str::trim) {
        if line.starts_with('[') {
            in_package = line == "[package]";
        } else if in_package {
            if let Some(rest) = line.strip_prefix("name") {
                let rest = rest.trim_start().strip_prefix('=')?.trim();
                return Some(rest.trim_matches('"').to_string());
            }
        }
    }
    None
}

/// The quoted strings of `members = [...]`, which may span lines.
fn members(manifest: &str) -> Vec<String> {
    let Some(at) = manifest.find("members") else {
        return Vec::new();
    };
    let rest = &manifest[at..];
    let (Some(open), Some(close)) = (rest.find('['), rest.find(']')) else {
        return Vec::new();
    };
    rest[open + 1..close]
        .split(',')
        .map(|s| s.trim().trim_matches('"').to_string())
        .filter(|s| !s.is_empty())
        .collect()
}

/// One file of a target: where it is and which module it is.
#[derive(Debug, Clone)]
pub struct SourceFile {
    /// Path shown in reports (relative to the workspace root).
    pub shown: String,
    /// Module path from the target's root (empty: the root).
    pub module: Vec<String>,
    pub text: String,
}

/// A reference from one file to another module's file.
#[derive(Debug, Clone, PartialEq, Eq, PartialOrd, Ord)]
pub struct Edge {
    pub from: usize,
    pub to: usize,
    /// 1-based line of the reference.
    pub line: usize,
    /// The path as written, `::`-joined.
    pub path: String,
}

/// The files of one package's targets: one list per target (library or binary).
pub fn package_targets(root: &Path, package: &Package) -> Result<Vec<Vec<SourceFile>>, String> {
    let src = root.join(&package.dir).join("src");
    let shown_base = if package.dir == Path::new(".") {
        PathBuf::from("src")
    } else {
        package.dir.join("src")
    };
    let mut files = Vec::new();
    rust_files(&src, &mut files)?;
    files.sort();
    // The library's (or main.rs's) tree: everything not under src/bin.
    let mut main_tree = Vec::new();
    let mut bins: BTreeMap<String, Vec<SourceFile>> = BTreeMap::new();
    for path in files {
        let rel = path.strip_prefix(&src).expect("found under src");
        let parts: Vec<String> = rel
            .iter()
            .map(|c| c.to_string_lossy().into_owned())
            .collect();
        let text = read(&path)?;
        let shown = shown_base.join(rel).to_string_lossy().into_owned();
        if parts.first().map(String::as_str) == Some("bin") && parts.len() >= 2 {
            let name = parts[1].trim_end_matches(".rs").to_string();
            let module = if parts.len() == 2 {
                Vec::new()
            } else {
                module_path(&parts[2..])
            };
            bins.entry(name).or_default().push(SourceFile {
                shown,
                module,
                text,
            });
        } else {
            main_tree.push(SourceFile {
                shown,
                module: module_path(&parts),
                text,
            });
        }
    }
    let mut targets = Vec::new();
    if !main_tree.is_empty() {
        targets.push(main_tree);
    }
    targets.extend(bins.into_values());
    Ok(targets)
}

fn rust_files(dir: &Path, out: &mut Vec<PathBuf>) -> Result<(), String> {
    let entries =
        std::fs::read_dir(dir).map_err(|e| format!("cannot list {}: {e}", dir.display()))?;
    for entry in entries {
        let path = entry.map_err(|e| e.to_string())?.path();
        if path.is_dir() {
            rust_files(&path, out)?;
        } else if path.extension().is_some_and(|e| e == "rs") {
            out.push(path);
        }
    }
    Ok(())
}

/// The module of a file from its path components below the target's root directory:
/// `a/b.rs` is `a::b`, `a/mod.rs` is `a`, `lib.rs` and `main.rs` at the top are the root.
fn module_path(parts: &[String]) -> Vec<String> {
    let mut m: Vec<String> = parts.to_vec();
    let last = m.pop().unwrap_or_default();
    let stem = last.trim_end_matches(".rs");
    let is_root = m.is_empty() && (stem == "lib" || stem == "main");
    if stem != "mod" && !is_root {
        m.push(stem.to_string());
    }
    m
}

#[derive(Debug, Clone, PartialEq)]
enum Tok {
    Ident(String),
    Path,
    Open,
    Close,
    Comma,
    Semi,
    Star,
    Other,
}

/// The tokens of Rust source that paths are made of, with their lines; comments, strings and
/// character literals are dropped.
fn tokens(src: &str) -> Vec<(Tok, usize)> {
    let b = src.as_bytes();
    let mut out = Vec::new();
    let (mut i, mut line) = (0, 1);
    let newlines = |s: &[u8]| s.iter().filter(|&&c| c == b'\n').count();
    while i < b.len() {
        let c = b[i];
        match c {
            b'\n' => {
                line += 1;
                i += 1;
            }
            b'/' if b.get(i + 1) == Some(&b'/') => {
                while i < b.len() && b[i] != b'\n' {
                    i += 1;
                }
            }
            b'/' if b.get(i + 1) == Some(&b'*') => {
                let (start, mut depth) = (i, 0);
                while i < b.len() {
                    if b[i] == b'/' && b.get(i + 1) == Some(&b'*') {
                        depth += 1;
                        i += 2;
                    } else if b[i] == b'*' && b.get(i + 1) == Some(&b'/') {
                        depth -= 1;
                        i += 2;
                        if depth == 0 {
                            break;
                        }
                    } else {
                        i += 1;
                    }
                }
                line += newlines(&b[start..i.min(b.len())]);
            }
            b'"' => {
                let start = i;
                i += 1;
                while i < b.len() && b[i] != b'"' {
                    i += if b[i] == b'\\' { 2 } else { 1 };
                }
                i += 1;
                line += newlines(&b[start..i.min(b.len())]);
            }
            b'r' if matches!(b.get(i + 1), Some(b'"' | b'#')) && raw_string_end(b, i).is_some() => {
                let end = raw_string_end(b, i).expect("checked");
                line += newlines(&b[i..end]);
                i = end;
            }
            b'\'' => {
                // A char literal ('x', '\n', '\u{..}') or a lifetime ('a).
                if b.get(i + 1) == Some(&b'\\') {
                    i += 2;
                    while i < b.len() && b[i] != b'\'' {
                        i += 1;
                    }
                    i += 1;
                } else if b.get(i + 2) == Some(&b'\'') {
                    i += 3;
                } else if let Some(len) = std::str::from_utf8(&b[i + 1..])
                    .ok()
                    .and_then(|s| s.chars().next())
                    .map(char::len_utf8)
                    .filter(|&l| b.get(i + 1 + l) == Some(&b'\''))
                {
                    i += len + 2;
                } else {
                    i += 1;
                }
            }
            b':' if b.get(i + 1) == Some(&b':') => {
                out.push((Tok::Path, line));
                i += 2;
            }
            b'{' => {
                out.push((Tok::Open, line));
                i += 1;
            }
            b'}' => {
                out.push((Tok::Close, line));
                i += 1;
            }
            b',' => {
                out.push((Tok::Comma, line));
                i += 1;
            }
            b';' => {
                out.push((Tok::Semi, line));
                i += 1;
            }
            b'*' => {
                out.push((Tok::Star, line));
                i += 1;
            }
            b'$' if src[i + 1..].starts_with("crate") => {
                out.push((Tok::Ident("crate".into()), line));
                i += 6;
            }
            c if c == b'_' || c.is_ascii_alphabetic() => {
                let start = i;
                while i < b.len() && (b[i] == b'_' || b[i].is_ascii_alphanumeric()) {
                    i += 1;
                }
                let word = &src[start..i];
                // Byte strings and raw identifiers: b"..", br"..", r#ident.
                if word == "b" && b.get(i) == Some(&b'"') {
                    continue;
                }
                if word == "br" && matches!(b.get(i), Some(b'"' | b'#')) {
                    if let Some(end) = raw_string_end(b, i - 1) {
                        line += newlines(&b[i..end]);
                        i = end;
                        continue;
                    }
                }
                if word == "r" && b.get(i) == Some(&b'#') {
                    i += 1;
                    continue;
                }
                out.push((Tok::Ident(word.to_string()), line));
            }
            c if c.is_ascii_whitespace() => i += 1,
            _ => {
                out.push((Tok::Other, line));
                i += 1;
            }
        }
    }
    out
}

/// The end (one past the closing quote and hashes) of a raw string starting with the `r` at
/// `at`, or `None` when it is not one.
fn raw_string_end(b: &[u8], at: usize) -> Option<usize> {
    let mut i = at + 1;
    let mut hashes = 0;
    while b.get(i) == Some(&b'#') {
        hashes += 1;
        i += 1;
    }
    if b.get(i) != Some(&b'"') {
        return None;
    }
    i += 1;
    while i < b.len() {
        if b[i] == b'"'
            && b[i + 1..]
                .iter()
                .take(hashes)
                .filter(|&&c| c == b'#')
                .count()
                == hashes
        {
            return Some(i + 1 + hashes);
        }
        i += 1;
    }
    Some(b.len())
}

/// A path found in a file: its segments from its anchor (`crate`, `super`, `self` or a first
/// name) and its line.
#[derive(Debug, Clone, PartialEq)]
struct FoundPath {
    segments: Vec<String>,
    line: usize,
    /// The inline modules around it, innermost last.
    inline: Vec<String>,
}

/// Every path in a file that starts at a name and goes on with `::`, use trees expanded, and
/// the inline modules the file declares (their paths below the file's module).
fn paths(src: &str) -> (Vec<FoundPath>, Vec<Vec<String>>) {
    let toks = tokens(src);
    let mut found = Vec::new();
    let mut declared = Vec::new();
    let mut inline: Vec<(String, usize)> = Vec::new();
    let mut depth = 0usize;
    let mut i = 0;
    while i < toks.len() {
        match &toks[i].0 {
            Tok::Open => depth += 1,
            Tok::Close => {
                depth = depth.saturating_sub(1);
                if inline.last().is_some_and(|(_, d)| *d == depth) {
                    inline.pop();
                }
            }
            Tok::Ident(w) if w == "mod" => {
                if let (Some((Tok::Ident(name), _)), Some((Tok::Open, _))) =
                    (toks.get(i + 1), toks.get(i + 2))
                {
                    inline.push((name.clone(), depth));
                    declared.push(inline.iter().map(|(n, _)| n.clone()).collect());
                    depth += 1;
                    i += 3;
                    continue;
                }
            }
            Tok::Ident(w) if w == "use" => {
                let names: Vec<String> = inline.iter().map(|(n, _)| n.clone()).collect();
                let mut j = i + 1;
                // `use ::x` names an extern crate.
                if toks.get(j).map(|t| &t.0) != Some(&Tok::Path) {
                    for (segments, line) in use_tree(&toks, &mut j, Vec::new()) {
                        found.push(FoundPath {
                            segments,
                            line,
                            inline: names.clone(),
                        });
                    }
                }
                i = j;
                continue;
            }
            Tok::Ident(w) => {
                let after_path = i > 0 && toks[i - 1].0 == Tok::Path;
                if !after_path && toks.get(i + 1).map(|t| &t.0) == Some(&Tok::Path) {
                    let mut segments = vec![w.clone()];
                    let line = toks[i].1;
                    let mut j = i + 1;
                    while toks.get(j).map(|t| &t.0) == Some(&Tok::Path) {
                        match toks.get(j + 1) {
                            Some((Tok::Ident(s), _)) => {
                                segments.push(s.clone());
                                j += 2;
                            }
                            _ => break,
                        }
                    }
                    found.push(FoundPath {
                        segments,
                        line,
                        inline: inline.iter().map(|(n, _)| n.clone()).collect(),
                    });
                    i = j;
                    continue;
                }
            }
            _ => {}
        }
        i += 1;
    }
    (found, declared)
}

/// The paths of a use tree starting at `toks[*j]`, each prefixed with `prefix`; `*j` ends
/// after the tree (at its `,`, `}` or `;`).
fn use_tree(
    toks: &[(Tok, usize)],
    j: &mut usize,
    prefix: Vec<String>,
) -> Vec<(Vec<String>, usize)> {
    let mut segs = prefix;
    let mut out = Vec::new();
    let line = toks.get(*j).map_or(0, |t| t.1);
    loop {
        match toks.get(*j).map(|t| &t.0) {
            Some(Tok::Ident(w)) if w == "as" => {
                *j += 2;
            }
            Some(Tok::Ident(s)) => {
                segs.push(s.clone());
                *j += 1;
            }
            Some(Tok::Path) => *j += 1,
            Some(Tok::Star) => *j += 1,
            Some(Tok::Open) => {
                *j += 1;
                loop {
                    match toks.get(*j).map(|t| &t.0) {
                        Some(Tok::Close) => {
                            *j += 1;
                            break;
                        }
                        Some(Tok::Comma) => *j += 1,
                        None => break,
                        _ => {
                            let before = *j;
                            out.extend(use_tree(toks, j, segs.clone()));
                            if *j == before {
                                *j += 1;
                            }
                        }
                    }
                }
                return out;
            }
            _ => break,
        }
    }
    // `use a::{self, b}` names `a` itself.
    if segs.last().map(String::as_str) == Some("self") && segs.len() > 1 {
        segs.pop();
    }
    if !segs.is_empty() {
        out.push((segs, line));
    }
    out
}

/// A module: a file, or an inline module in one.
#[derive(Debug, Clone)]
pub struct Node {
    /// The file, and for an inline module its path in the file (`(mod tests)`).
    pub shown: String,
    pub module: Vec<String>,
}

/// The module graph of one target: its modules and the edges between them.
pub struct Graph {
    pub nodes: Vec<Node>,
    pub edges: Vec<Edge>,
}

/// Builds the graph of one target's files by the rules in the module doc.
pub fn graph(files: Vec<SourceFile>) -> Graph {
    let mut nodes = Vec::new();
    let mut found = Vec::new();
    for f in &files {
        let (p, declared) = paths(&f.text);
        nodes.push(Node {
            shown: f.shown.clone(),
            module: f.module.clone(),
        });
        for d in declared {
            let mut module = f.module.clone();
            module.extend(d.iter().cloned());
            nodes.push(Node {
                shown: format!("{} (mod {})", f.shown, d.join("::")),
                module,
            });
        }
        found.push((f.module.clone(), p));
    }
    let index: BTreeMap<Vec<String>, usize> = nodes
        .iter()
        .enumerate()
        .map(|(i, n)| (n.module.clone(), i))
        .collect();
    let mut edges = BTreeSet::new();
    for (module, ps) in found {
        for p in ps {
            let mut here = module.clone();
            here.extend(p.inline.iter().cloned());
            let Some(&from) = index.get(&here) else {
                continue;
            };
            let Some(to) = resolve(&here, &p, &index) else {
                continue;
            };
            // Itself, an ancestor, or the root: not an edge.
            if to == from || here.starts_with(&nodes[to].module) {
                continue;
            }
            edges.insert(Edge {
                from,
                to,
                line: p.line,
                path: p.segments.join("::"),
            });
        }
    }
    Graph {
        nodes,
        edges: edges.into_iter().collect(),
    }
}

/// The node of the deepest module a path written in module `here` names, or `None` for a path
/// outside the target (an extern crate, a type's associated item).
fn resolve(here: &[String], p: &FoundPath, index: &BTreeMap<Vec<String>, usize>) -> Option<usize> {
    let here = here.to_vec();
    let mut segs = p.segments.iter().peekable();
    let mut abs: Vec<String> = match segs.peek().map(|s| s.as_str()) {
        Some("crate") => {
            segs.next();
            Vec::new()
        }
        Some("self") => {
            segs.next();
            here.clone()
        }
        Some("super") => {
            let mut base = here.clone();
            while segs.peek().map(|s| s.as_str()) == Some("super") {
                segs.next();
                base.pop()?;
            }
            base
        }
        Some(first) => {
            // A child module of the module it is written in, else not ours.
            let mut child = here.clone();
            child.push(first.to_string());
            if !index.contains_key(&child) {
                return None;
            }
            here.clone()
        }
        None => return None,
    };
    let mut best = None;
    for s in segs {
        abs.push(s.clone());
        if let Some(&i) = index.get(&abs) {
            best = Some(i);
        }
    }
    // A path that names no module below its anchor names the anchor's own module (the longest
    // prefix of it that is a node).
    if best.is_none() {
        let mut base = abs;
        while !base.is_empty() {
            base.pop();
            if let Some(&i) = index.get(&base) {
                return Some(i);
            }
        }
    }
    best
}

/// The strongly connected components of more than one node (Tarjan's algorithm), each sorted,
/// in order of their first node.
pub fn cycles(n: usize, edges: &[(usize, usize)]) -> Vec<Vec<usize>> {
    let mut adj = vec![Vec::new(); n];
    for &(a, b) in edges {
        if a != b && !adj[a].contains(&b) {
            adj[a].push(b);
        }
    }
    struct State {
        index: Vec<Option<usize>>,
        low: Vec<usize>,
        on_stack: Vec<bool>,
        stack: Vec<usize>,
        next: usize,
        out: Vec<Vec<usize>>,
    }
    fn visit(v: usize, adj: &[Vec<usize>], s: &mut State) {
        s.index[v] = Some(s.next);
        s.low[v] = s.next;
        s.next += 1;
        s.stack.push(v);
        s.on_stack[v] = true;
        for &w in &adj[v] {
            match s.index[w] {
                None => {
                    visit(w, adj, s);
                    s.low[v] = s.low[v].min(s.low[w]);
                }
                Some(iw) if s.on_stack[w] => s.low[v] = s.low[v].min(iw),
                Some(_) => {}
            }
        }
        if Some(s.low[v]) == s.index[v] {
            let mut comp = Vec::new();
            loop {
                let w = s.stack.pop().expect("v is on the stack");
                s.on_stack[w] = false;
                comp.push(w);
                if w == v {
                    break;
                }
            }
            if comp.len() > 1 {
                comp.sort_unstable();
                s.out.push(comp);
            }
        }
    }
    let mut s = State {
        index: vec![None; n],
        low: vec![0; n],
        on_stack: vec![false; n],
        stack: Vec::new(),
        next: 0,
        out: Vec::new(),
    };
    for v in 0..n {
        if s.index[v].is_none() {
            visit(v, &adj, &mut s);
        }
    }
    s.out.sort();
    s.out
}

/// A shortest cycle through `start` within `comp` (breadth-first), `start` first.
pub fn cycle_through(start: usize, comp: &[usize], edges: &[(usize, usize)]) -> Vec<usize> {
    let inside = |v: &usize| comp.contains(v);
    let mut prev: BTreeMap<usize, usize> = BTreeMap::new();
    let mut queue = VecDeque::from([start]);
    while let Some(v) = queue.pop_front() {
        for &(a, b) in edges {
            if a != v || !inside(&b) {
                continue;
            }
            if b == start {
                let mut path = vec![v];
                let mut at = v;
                while at != start {
                    at = prev[&at];
                    path.push(at);
                }
                path.reverse();
                return path;
            }
            if let std::collections::btree_map::Entry::Vacant(e) = prev.entry(b) {
                e.insert(v);
                queue.push_back(b);
            }
        }
    }
    vec![start]
}

/// The report of one target's cycles ("" when there are none), and how many it has.
pub fn report(g: &Graph) -> (String, usize) {
    let pairs: Vec<(usize, usize)> = g.edges.iter().map(|e| (e.from, e.to)).collect();
    let comps = cycles(g.nodes.len(), &pairs);
    let mut out = String::new();
    for comp in &comps {
        let names: Vec<&str> = comp.iter().map(|&i| g.nodes[i].shown.as_str()).collect();
        out.push_str(&format!("  cycle among {}:\n", names.join(", ")));
        let ring = cycle_through(comp[0], comp, &pairs);
        let mut shown: Vec<&str> = ring.iter().map(|&i| g.nodes[i].shown.as_str()).collect();
        shown.push(&g.nodes[comp[0]].shown);
        out.push_str(&format!("    e.g. {}\n", shown.join(" -> ")));
        // Each pair of files once: its first reference, and how many more there are.
        let inside: Vec<&Edge> = g
            .edges
            .iter()
            .filter(|e| comp.contains(&e.from) && comp.contains(&e.to))
            .collect();
        let mut pairs_seen: BTreeMap<(usize, usize), (&Edge, usize)> = BTreeMap::new();
        for e in inside {
            pairs_seen
                .entry((e.from, e.to))
                .and_modify(|(_, n)| *n += 1)
                .or_insert((e, 0));
        }
        for (e, more) in pairs_seen.values() {
            let more = match more {
                0 => String::new(),
                n => format!(" and {n} more"),
            };
            out.push_str(&format!(
                "    {}:{} -> {} ({}){more}\n",
                g.nodes[e.from].shown, e.line, g.nodes[e.to].shown, e.path
            ));
        }
    }
    (out, comps.len())
}

/// `cargo xtask cycles [CRATE...]`: check the named packages (package name or directory; all
/// of them without arguments). Exit status 1 when any has a cycle.
pub fn command(root: &Path, args: &[String]) -> std::process::ExitCode {
    use std::process::ExitCode;
    let packages = match workspace_packages(root) {
        Ok(p) => p,
        Err(e) => {
            eprintln!("{e}");
            return ExitCode::FAILURE;
        }
    };
    let mut chosen = Vec::new();
    for a in args {
        let dir = Path::new(a.trim_end_matches('/'));
        match packages.iter().find(|p| p.name == *a || p.dir == dir) {
            Some(p) => chosen.push(p.clone()),
            None => {
                let names: Vec<&str> = packages.iter().map(|p| p.name.as_str()).collect();
                eprintln!("no workspace package {a} (packages: {})", names.join(", "));
                return ExitCode::from(2);
            }
        }
    }
    if args.is_empty() {
        chosen = packages;
    }
    let mut total = 0;
    for p in &chosen {
        let targets = match package_targets(root, p) {
            Ok(t) => t,
            Err(e) => {
                eprintln!("{e}");
                return ExitCode::FAILURE;
            }
        };
        let mut text = String::new();
        let mut count = 0;
        for files in targets {
            let (r, n) = report(&graph(files));
            text.push_str(&r);
            count += n;
        }
        if count == 0 {
            println!("{}: no import cycles", p.name);
        } else {
            println!("{}: {count} import cycle(s)\n{text}", p.name);
        }
        total += count;
    }
    if total == 0 {
        ExitCode::SUCCESS
    } else {
        ExitCode::FAILURE
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cycles_finds_each_component_of_a_synthetic_graph() {
        // 0 <-> 1; 2 -> 3 -> 4 -> 2 with 4 -> 5; 5 alone; 6 -> 6 (a self-loop is no cycle).
        let edges = [
            (0, 1),
            (1, 0),
            (2, 3),
            (3, 4),
            (4, 2),
            (4, 5),
            (6, 6),
            (1, 2),
        ];
        assert_eq!(cycles(7, &edges), vec![vec![0, 1], vec![2, 3, 4]]);
        assert_eq!(cycle_through(2, &[2, 3, 4], &edges), vec![2, 3, 4]);
        assert_eq!(cycle_through(1, &[0, 1], &edges), vec![1, 0]);
        // A tree and a diamond have none.
        assert!(cycles(4, &[(0, 1), (0, 2), (1, 3), (2, 3)]).is_empty());
    }

    fn file(path: &str, text: &str) -> SourceFile {
        let parts: Vec<String> = path.split('/').map(str::to_string).collect();
        SourceFile {
            shown: path.to_string(),
            module: module_path(&parts),
            text: text.to_string(),
        }
    }

    fn edges_of(files: Vec<SourceFile>) -> Vec<(String, String)> {
        let g = graph(files);
        g.edges
            .iter()
            .map(|e| (g.nodes[e.from].shown.clone(), g.nodes[e.to].shown.clone()))
            .collect::<BTreeSet<_>>()
            .into_iter()
            .collect()
    }

    #[test]
    fn edges_follow_the_rules() {
        let e = |a: &str, b: &str| (a.to_string(), b.to_string());
        let files = vec![
            file("lib.rs", "mod a; mod b; mod p; pub use a::*;"),
            // A use tree, an inline path, a comment and a string that name b (not edges).
            file(
                "a.rs",
                "use crate::{b::{self, X}, p::q::Y};\n// crate::b::Z\nfn f() { let s = \"crate::b\"; crate::p::g(); }",
            ),
            file("b.rs", "use super::a::f; use std::fmt;"),
            // A parent and its children: up is never an edge, down is.
            file("p/mod.rs", "mod q; pub use q::Y; use crate::a;"),
            file(
                "p/q.rs",
                "use super::*; use crate::p::thing; mod tests { use super::super::super::b; }",
            ),
        ];
        assert_eq!(
            edges_of(files),
            vec![
                e("a.rs", "b.rs"),
                e("a.rs", "p/mod.rs"),
                e("a.rs", "p/q.rs"),
                e("b.rs", "a.rs"),
                e("lib.rs", "a.rs"),
                e("p/mod.rs", "a.rs"),
                e("p/mod.rs", "p/q.rs"),
                e("p/q.rs (mod tests)", "b.rs"),
            ]
        );
    }

    #[test]
    fn report_names_the_files_and_lines_of_a_cycle() {
        let g = graph(vec![
            file("lib.rs", "mod a; mod b; mod c;"),
            file("a.rs", "use crate::b::X;"),
            file("b.rs", "\nfn f() { super::c::g() }"),
            file("c.rs", "use crate::a::Y;"),
        ]);
        let (text, n) = report(&g);
        assert_eq!(n, 1);
        assert!(text.contains("a.rs -> b.rs -> c.rs -> a.rs"), "{text}");
        assert!(text.contains("b.rs:2 -> c.rs (super::c::g)"), "{text}");
    }

    #[test]
    fn an_inline_module_is_its_own_node() {
        // A test module driving a higher layer: no cycle.
        let tests_only = graph(vec![
            file("lib.rs", "mod api; mod result;"),
            file("api.rs", "use crate::result::guard;"),
            file(
                "result.rs",
                "pub fn guard() {}\n#[cfg(test)]\nmod tests { use crate::api::f; }",
            ),
        ]);
        assert_eq!(report(&tests_only).1, 0);
        // An inline module that is used is part of its file's cycles.
        let (text, n) = report(&graph(vec![
            file("lib.rs", "mod a; mod b;"),
            file("a.rs", "pub use inner::*; mod inner { use crate::b::X; }"),
            file("b.rs", "use crate::a::Y;"),
        ]));
        assert_eq!(n, 1);
        assert!(
            text.contains("a.rs -> a.rs (mod inner) -> b.rs -> a.rs"),
            "{text}"
        );
    }

    #[test]
    fn module_paths_of_files() {
        let m = |p: &str| module_path(&p.split('/').map(str::to_string).collect::<Vec<_>>());
        assert!(m("lib.rs").is_empty() && m("main.rs").is_empty());
        assert_eq!(m("a/mod.rs"), ["a"]);
        assert_eq!(m("a/b.rs"), ["a", "b"]);
        assert_eq!(m("a.rs"), ["a"]);
    }

    #[test]
    fn char_literals_and_lifetimes_do_not_hide_code() {
        let (p, _) = paths("fn f<'a>(x: &'a str) -> char { let c = '\"'; crate::a::g(); '{' }");
        assert_eq!(p.len(), 1);
        assert_eq!(p[0].segments, ["crate", "a", "g"]);
    }
}
