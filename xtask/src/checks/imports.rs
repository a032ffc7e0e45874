//! Import cycles between a crate's files: which file names which through `crate::`, `super::`,
//! `self::` and child-module paths, and the strongly connected sets of that graph. A module's
//! `mod child;` declaration is no import; `pub use child::Item` in the parent is.
//!
//! The reading is textual (comments, strings and `#[cfg]` are not told apart from code beyond
//! stripping the first two), which is what a reader of the files sees too.

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

/// A module's path from the crate root (`[]` is the root).
type ModPath = Vec<String>;

/// One file's imports: the file it names and the names it takes from it.
pub type Edges = BTreeMap<PathBuf, BTreeMap<PathBuf, BTreeSet<String>>>;

/// The files of the crate whose root is `root` (`src/lib.rs`, `src/main.rs`): every `.rs`
/// under its folder but `bin/` (each binary is a crate of its own), by module path.
fn modules(root: &Path) -> BTreeMap<ModPath, PathBuf> {
    let dir = root.parent().unwrap_or(Path::new("."));
    let mut found = BTreeMap::new();
    found.insert(Vec::new(), root.to_path_buf());
    let mut stack = vec![(dir.to_path_buf(), Vec::new())];
    while let Some((folder, prefix)) = stack.pop() {
        let Ok(entries) = std::fs::read_dir(&folder) else {
            continue;
        };
        for path in entries.flatten().map(|e| e.path()) {
            let name = path.file_stem().map(|s| s.to_string_lossy().into_owned());
            let Some(name) = name else { continue };
            let mut module: ModPath = prefix.clone();
            if path.is_dir() {
                if prefix.is_empty() && name == "bin" {
                    continue;
                }
                module.push(name);
                stack.push((path, module));
            } else if path.extension().is_some_and(|e| e == "rs") && path != root {
                if name != "mod" {
                    module.push(name);
                }
                found.insert(module, path);
            }
        }
    }
    found
}

/// Rust source without its comments, string and character literals (each replaced by a space),
/// lifetimes kept as they are.
fn strip(source: &str) -> String {
    let chars: Vec<char> = source.chars().collect();
    let mut out = String::with_capacity(source.len());
    let mut i = 0;
    while i < chars.len() {
        let c = chars[i];
        let next = chars.get(i + 1).copied();
        if c == '/' && next == Some('/') {
            while i < chars.len() && chars[i] != '\n' {
                i += 1;
            }
        } else if c == '/' && next == Some('*') {
            let mut depth = 0;
            while i < chars.len() {
                if chars[i] == '/' && chars.get(i + 1) == Some(&'*') {
                    depth += 1;
                    i += 2;
                } else if chars[i] == '*' && chars.get(i + 1) == Some(&'/') {
                    depth -= 1;
                    i += 2;
                    if depth == 0 {
                        break;
                    }
                } else {
                    i += 1;
                }
            }
            out.push(' ');
        } else if c == '"' || (c == 'r' && matches!(next, Some('"') | Some('#'))) {
            i = skip_string(&chars, i);
            out.push(' ');
        } else if c == '\'' && is_char_literal(&chars, i) {
            i += 1;
            while i < chars.len() && chars[i] != '\'' {
                i += if chars[i] == '\\' { 2 } else { 1 };
            }
            i += 1;
            out.push(' ');
        } else {
            out.push(c);
            i += 1;
        }
    }
    out
}

/// The index just past the string literal that starts at `i` (plain or raw).
fn skip_string(chars: &[char], mut i: usize) -> usize {
    if chars[i] == 'r' {
        i += 1;
        let mut hashes = 0;
        while chars.get(i) == Some(&'#') {
            hashes += 1;
            i += 1;
        }
        if chars.get(i) != Some(&'"') {
            return i;
        }
        i += 1;
        while i < chars.len() {
            if chars[i] == '"' && (1..=hashes).all(|k| chars.get(i + k) == Some(&'#')) {
                return i + 1 + hashes;
            }
            i += 1;
        }
        return i;
    }
    i += 1;
    while i < chars.len() && chars[i] != '"' {
        i += if chars[i] == '\\' { 2 } else { 1 };
    }
    i + 1
}

/// Whether the quote at `i` opens a character literal rather than a lifetime.
fn is_char_literal(chars: &[char], i: usize) -> bool {
    matches!(
        (chars.get(i + 1), chars.get(i + 2)),
        (Some('\\'), _) | (Some(_), Some('\''))
    )
}

/// Tokens: identifiers (with `$crate` as `crate`), `::`, and single punctuation characters.
fn tokens(code: &str) -> Vec<String> {
    let chars: Vec<char> = code.chars().collect();
    let mut out = Vec::new();
    let mut i = 0;
    while i < chars.len() {
        let c = chars[i];
        if c.is_alphanumeric() || c == '_' {
            let start = i;
            while i < chars.len() && (chars[i].is_alphanumeric() || chars[i] == '_') {
                i += 1;
            }
            out.push(chars[start..i].iter().collect());
        } else if c == ':' && chars.get(i + 1) == Some(&':') {
            out.push("::".to_string());
            i += 2;
        } else if c == '$' || c.is_whitespace() {
            i += 1;
        } else {
            out.push(c.to_string());
            i += 1;
        }
    }
    out
}

/// The paths a file names, each with the module it is named from (its own, or an inline
/// module's inside it): `use` trees expanded, and `a::b::c` sequences in code.
fn paths(module: &ModPath, code: &str) -> Vec<(ModPath, Vec<String>)> {
    let tokens = tokens(code);
    let mut out = Vec::new();
    // Inline modules: (name, the brace depth at which they close).
    let mut inline: Vec<(String, usize)> = Vec::new();
    let mut depth = 0;
    let mut i = 0;
    while i < tokens.len() {
        match tokens[i].as_str() {
            "{" => depth += 1,
            "}" => {
                depth -= 1;
                if inline.last().is_some_and(|(_, d)| *d == depth) {
                    inline.pop();
                }
            }
            "mod" if tokens.get(i + 2).is_some_and(|t| t == "{") => {
                inline.push((tokens[i + 1].clone(), depth));
                depth += 1;
                i += 3;
                continue;
            }
            "use" => {
                let end = (i..tokens.len())
                    .find(|&k| tokens[k] == ";")
                    .unwrap_or(tokens.len());
                let mut trees = Vec::new();
                use_tree(&tokens[i + 1..end], Vec::new(), &mut trees);
                let from = here(module, &inline);
                out.extend(trees.into_iter().map(|p| (from.clone(), p)));
                i = end + 1;
                continue;
            }
            _ => {}
        }
        if tokens.get(i + 1).is_some_and(|t| t == "::") && is_ident(&tokens[i]) {
            let previous = i.checked_sub(1).map(|k| tokens[k].as_str());
            if previous != Some("::") {
                let mut path = vec![tokens[i].clone()];
                let mut k = i + 1;
                while tokens.get(k).is_some_and(|t| t == "::")
                    && tokens.get(k + 1).is_some_and(|t| is_ident(t))
                {
                    path.push(tokens[k + 1].clone());
                    k += 2;
                }
                out.push((here(module, &inline), path));
                i = k;
                continue;
            }
        }
        i += 1;
    }
    out
}

/// The module at a point of a file: the file's, then the inline modules open there.
fn here(module: &ModPath, inline: &[(String, usize)]) -> ModPath {
    let mut m = module.clone();
    m.extend(inline.iter().map(|(n, _)| n.clone()));
    m
}

fn is_ident(token: &str) -> bool {
    token
        .chars()
        .next()
        .is_some_and(|c| c.is_alphabetic() || c == '_')
}

/// Expands one `use` tree (`a::{b, c::d as e, f::*}`) into its paths.
fn use_tree(tokens: &[String], prefix: Vec<String>, out: &mut Vec<Vec<String>>) {
    let mut path = prefix;
    let mut i = 0;
    while i < tokens.len() {
        match tokens[i].as_str() {
            "::" | "pub" | "(" | ")" => i += 1,
            "{" => {
                let mut depth = 0;
                let mut start = i + 1;
                for k in i..tokens.len() {
                    match tokens[k].as_str() {
                        "{" => depth += 1,
                        "}" => depth -= 1,
                        "," if depth == 1 => {
                            use_tree(&tokens[start..k], path.clone(), out);
                            start = k + 1;
                        }
                        _ => {}
                    }
                    if depth == 0 {
                        use_tree(&tokens[start..k], path.clone(), out);
                        return;
                    }
                }
                return;
            }
            "as" | "*" => break,
            token if is_ident(token) => {
                path.push(token.to_string());
                i += 1;
            }
            _ => i += 1,
        }
    }
    if !path.is_empty() {
        out.push(path);
    }
}

/// The module a path names from `from`, as deep as the crate's modules go, and the name it
/// takes there; `None` for another crate's path or a local item.
fn resolve(
    from: &ModPath,
    path: &[String],
    known: &BTreeSet<ModPath>,
) -> Option<(ModPath, String)> {
    let mut at = from.clone();
    let mut rest = path;
    match path.first()?.as_str() {
        "crate" => {
            at.clear();
            rest = &path[1..];
        }
        "self" => rest = &path[1..],
        "super" => {
            while rest.first().is_some_and(|s| s == "super") {
                at.pop()?;
                rest = &rest[1..];
            }
        }
        first => {
            let mut child = at.clone();
            child.push(first.to_string());
            if !known.contains(&child) {
                return None;
            }
        }
    }
    for segment in rest {
        let mut deeper = at.clone();
        deeper.push(segment.clone());
        if !known.contains(&deeper) {
            return Some((at, segment.clone()));
        }
        at = deeper;
    }
    let name = at.last().cloned().unwrap_or_else(|| "crate".to_string());
    at.pop();
    if !known.contains(&at) {
        return None;
    }
    Some((at, name))
}

/// The import graph of the crate rooted at `root` (its file paths as they are read).
pub fn graph(root: &Path) -> Edges {
    let files = modules(root);
    // Inline modules count as their file's.
    let mut owner: BTreeMap<ModPath, PathBuf> = files.clone();
    let mut read: Vec<(ModPath, PathBuf, String)> = Vec::new();
    for (module, file) in &files {
        let code = strip(&std::fs::read_to_string(file).unwrap_or_default());
        let tokens = tokens(&code);
        for w in tokens.windows(3) {
            if w[0] == "mod" && w[2] == "{" {
                let mut inner = module.clone();
                inner.push(w[1].clone());
                owner.entry(inner).or_insert_with(|| file.clone());
            }
        }
        read.push((module.clone(), file.clone(), code));
    }
    let known: BTreeSet<ModPath> = owner.keys().cloned().collect();
    let mut edges = Edges::new();
    for (module, file, code) in read {
        let mut out: BTreeMap<PathBuf, BTreeSet<String>> = BTreeMap::new();
        for (from, path) in paths(&module, &code) {
            let Some((target, name)) = resolve(&from, &path, &known) else {
                continue;
            };
            let (target, name) = child_named(&target, name, &known);
            let Some(target_file) = owner.get(&target) else {
                continue;
            };
            if *target_file != file {
                out.entry(target_file.clone()).or_default().insert(name);
            }
        }
        edges.insert(file, out);
    }
    edges
}

/// A path that ends on a module (`use super::chase`) names that module's file.
fn child_named(at: &ModPath, name: String, known: &BTreeSet<ModPath>) -> (ModPath, String) {
    let mut child = at.clone();
    child.push(name.clone());
    if known.contains(&child) {
        (child, name)
    } else {
        (at.clone(), name)
    }
}

/// The graph's strongly connected sets of more than one file (Tarjan's algorithm).
pub fn cycles(edges: &Edges) -> Vec<Vec<PathBuf>> {
    let nodes: Vec<&PathBuf> = edges.keys().collect();
    let index_of: BTreeMap<&PathBuf, usize> =
        nodes.iter().enumerate().map(|(i, n)| (*n, i)).collect();
    let next: Vec<Vec<usize>> = nodes
        .iter()
        .map(|n| {
            edges[*n]
                .keys()
                .filter_map(|t| index_of.get(t).copied())
                .collect()
        })
        .collect();
    let mut tarjan = Tarjan {
        next: &next,
        index: vec![None; nodes.len()],
        low: vec![0; nodes.len()],
        on_stack: vec![false; nodes.len()],
        stack: Vec::new(),
        counter: 0,
        found: Vec::new(),
    };
    for v in 0..nodes.len() {
        if tarjan.index[v].is_none() {
            tarjan.visit(v);
        }
    }
    tarjan
        .found
        .into_iter()
        .filter(|set| set.len() > 1)
        .map(|set| {
            let mut files: Vec<PathBuf> = set.into_iter().map(|i| nodes[i].clone()).collect();
            files.sort();
            files
        })
        .collect()
}

struct Tarjan<'a> {
    next: &'a [Vec<usize>],
    index: Vec<Option<usize>>,
    low: Vec<usize>,
    on_stack: Vec<bool>,
    stack: Vec<usize>,
    counter: usize,
    found: Vec<Vec<usize>>,
}

impl Tarjan<'_> {
    fn visit(&mut self, v: usize) {
        self.index[v] = Some(self.counter);
        self.low[v] = self.counter;
        self.counter += 1;
        self.stack.push(v);
        self.on_stack[v] = true;
        for &w in &self.next[v] {
            match self.index[w] {
                None => {
                    self.visit(w);
                    self.low[v] = self.low[v].min(self.low[w]);
                }
                Some(iw) if self.on_stack[w] => self.low[v] = self.low[v].min(iw),
                _ => {}
            }
        }
        if Some(self.low[v]) == self.index[v] {
            let mut set = Vec::new();
            while let Some(w) = self.stack.pop() {
                self.on_stack[w] = false;
                set.push(w);
                if w == v {
                    break;
                }
            }
            self.found.push(set);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn module(parts: &[&str]) -> ModPath {
        parts.iter().map(|s| s.to_string()).collect()
    }

    #[test]
    fn use_trees_expand_into_paths() {
        let t = tokens("crate::a::{b, c::{d as e, f}, g::*}");
        let mut out = Vec::new();
        use_tree(&t, Vec::new(), &mut out);
        let joined: Vec<String> = out.iter().map(|p| p.join("::")).collect();
        assert_eq!(
            joined,
            [
                "crate::a::b",
                "crate::a::c::d",
                "crate::a::c::f",
                "crate::a::g"
            ]
        );
    }

    #[test]
    fn comments_and_strings_name_nothing() {
        let code = strip(
            "let a = \"crate::x::y\"; // crate::z\n/* super::w */ 'c'; r#\"self::q\"#; x::<'a>",
        );
        let found = paths(&module(&["m"]), &code);
        let joined: Vec<String> = found.iter().map(|(_, p)| p.join("::")).collect();
        assert_eq!(joined, ["x"]);
    }

    #[test]
    fn paths_resolve_to_the_deepest_module_and_inline_modules_to_their_file() {
        let known: BTreeSet<ModPath> = [
            module(&[]),
            module(&["a"]),
            module(&["a", "b"]),
            module(&["c"]),
        ]
        .into();
        let path = |s: &str| s.split("::").map(str::to_string).collect::<Vec<_>>();
        let from = module(&["a", "b"]);
        assert_eq!(
            resolve(&from, &path("super::super::c::f"), &known),
            Some((module(&["c"]), "f".to_string()))
        );
        assert_eq!(
            resolve(&module(&["a"]), &path("b::g"), &known),
            Some((module(&["a", "b"]), "g".to_string()))
        );
        assert_eq!(resolve(&from, &path("std::fs::read"), &known), None);
        let code = strip("mod tests { use super::*; fn f() { crate::c::h(); } }");
        let found = paths(&module(&["a"]), &code);
        assert_eq!(found[0].0, module(&["a", "tests"]));
        assert_eq!(found[1].1, path("crate::c::h"));
    }

    #[test]
    fn a_loop_of_three_files_is_one_cycle_and_a_chain_is_none() {
        let f = |s: &str| PathBuf::from(s);
        let names = |t: &str| BTreeMap::from([(f(t), BTreeSet::from(["x".to_string()]))]);
        let mut edges: Edges = BTreeMap::new();
        edges.insert(f("a"), names("b"));
        edges.insert(f("b"), names("c"));
        edges.insert(f("c"), names("d"));
        edges.insert(f("d"), BTreeMap::new());
        assert!(cycles(&edges).is_empty());
        edges.insert(f("c"), names("a"));
        assert_eq!(cycles(&edges), [vec![f("a"), f("b"), f("c")]]);
    }
}
