//! No import cycles between the source files of any crate of the workspace.
//!
//! Every `use` of a `crate::`, `super::` or `self::` path (and every such path written
//! inline in the code) is an arrow from the file that writes it to the file of the module
//! it names; a re-export (`pub use`) is not: it is the module's face, not a dependency of
//! its code. Code under `#[cfg(test)]` is left
//! out: tests may reach anywhere. Each crate under `crates/` is read on its own (a path
//! into another crate is not an arrow within this one); a crate's library (`src/lib.rs`
//! and its modules) and program (`src/main.rs`, `src/cli/`) are read apart. Any circle of
//! arrows fails the test, which prints it with the names that tie it. A module's `mod.rs`
//! may name its children (a registry, a dispatch) only if they do not import it back: what
//! they share lives in a sibling file (`optim/problem.rs`, `surface/data.rs`,
//! `cli/args.rs`).

use std::collections::{BTreeMap, BTreeSet};
use std::fs;
use std::path::{Path, PathBuf};

#[test]
fn source_files_import_no_cycle() {
    // Every crate of the workspace: this one and its siblings under `crates/`.
    let crates = Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
    let mut circles = Vec::new();
    let mut checked = Vec::new();
    for entry in fs::read_dir(&crates).unwrap() {
        let src = entry.unwrap().path().join("src");
        if !src.is_dir() {
            continue;
        }
        let files = rust_files(&src);
        checked.push((src.display().to_string(), files.len()));
        for program in [false, true] {
            let modules: BTreeMap<Vec<String>, PathBuf> = files
                .iter()
                .filter_map(|f| {
                    let rel = f.strip_prefix(&src).ok()?;
                    (is_program(rel) == program).then(|| (module_path(rel), rel.to_path_buf()))
                })
                .collect();
            let graph = import_graph(&src, &modules);
            let name = src.display();
            circles.extend(
                cycles(&graph)
                    .into_iter()
                    .map(|(_, text)| format!("{name}: {text}")),
            );
        }
    }
    // The tracer, the lab and the program, each with its files.
    assert_eq!(checked.len(), 3, "{checked:?}");
    assert!(checked.iter().all(|(_, n)| *n >= 10), "{checked:?}");
    assert!(
        circles.is_empty(),
        "import cycles between source files:\n{}",
        circles.join("\n")
    );
}

/// The checker sees a circle that is there: a small crate whose `a` and `b` import each
/// other through a `use` tree and an inline path.
#[test]
fn the_checker_finds_a_planted_cycle() {
    let dir = std::env::temp_dir().join(format!("outlinefit-cycles-{}", std::process::id()));
    let src = dir.join("src");
    fs::create_dir_all(src.join("a")).unwrap();
    fs::write(src.join("lib.rs"), "pub mod a;\npub mod b;\n").unwrap();
    fs::write(
        src.join("a/mod.rs"),
        "pub mod inner;\nuse crate::{b::{self, Thing as T}};\n#[cfg(test)]\nmod tests { use crate::b::X; }\n",
    )
    .unwrap();
    fs::write(src.join("a/inner.rs"), "pub struct Y;\n").unwrap();
    fs::write(
        src.join("b.rs"),
        "// use crate::a::Z; (a comment)\nfn f() -> crate::a::inner::Y { let s = \"crate::a::W\"; todo!() }\n",
    )
    .unwrap();
    let modules: BTreeMap<Vec<String>, PathBuf> = rust_files(&src)
        .iter()
        .map(|f| {
            let rel = f.strip_prefix(&src).unwrap();
            (module_path(rel), rel.to_path_buf())
        })
        .collect();
    let graph = import_graph(&src, &modules);
    let found = cycles(&graph);
    fs::remove_dir_all(&dir).ok();
    // a/mod.rs -> b.rs (use tree), b.rs -> a/inner.rs (inline path): no circle of files.
    assert!(found.is_empty(), "{found:?}");
    assert_eq!(
        graph[Path::new("b.rs")].keys().collect::<Vec<_>>(),
        vec![Path::new("a/inner.rs")]
    );
    // The same crate with b importing a's own file: one circle.
    let mut graph = graph;
    graph
        .get_mut(Path::new("b.rs"))
        .unwrap()
        .insert(PathBuf::from("a/mod.rs"), BTreeSet::from(["Z".to_string()]));
    let found = cycles(&graph);
    assert_eq!(found.len(), 1, "{found:?}");
    let (files, text) = &found[0];
    assert_eq!(files.len(), 2);
    assert!(text.contains("a/mod.rs -> b.rs") && text.contains("b.rs -> a/mod.rs"));
}

/// Arrows between files: file -> (imported file -> names taken from it).
type Graph = BTreeMap<PathBuf, BTreeMap<PathBuf, BTreeSet<String>>>;

fn rust_files(dir: &Path) -> Vec<PathBuf> {
    let mut out = Vec::new();
    let mut stack = vec![dir.to_path_buf()];
    while let Some(d) = stack.pop() {
        for entry in fs::read_dir(&d).unwrap() {
            let p = entry.unwrap().path();
            if p.is_dir() {
                stack.push(p);
            } else if p.extension().is_some_and(|e| e == "rs") {
                out.push(p);
            }
        }
    }
    out.sort();
    out
}

/// True for the program's files (`main.rs` and `cli/`), false for the library's.
fn is_program(rel: &Path) -> bool {
    rel == Path::new("main.rs") || rel.starts_with("cli")
}

/// The module a file holds: `a.rs` and `a/mod.rs` are `a`, `a/b.rs` is `a::b`, the crate
/// roots are the empty path.
fn module_path(rel: &Path) -> Vec<String> {
    let mut parts: Vec<String> = rel
        .iter()
        .map(|s| s.to_string_lossy().into_owned())
        .collect();
    let last = parts.pop().unwrap_or_default();
    let stem = last.trim_end_matches(".rs");
    if !matches!(stem, "mod" | "lib" | "main") {
        parts.push(stem.to_string());
    }
    parts
}

fn import_graph(src: &Path, modules: &BTreeMap<Vec<String>, PathBuf>) -> Graph {
    let mut graph = Graph::new();
    for (module, rel) in modules {
        let text = fs::read_to_string(src.join(rel)).unwrap();
        let edges = graph.entry(rel.clone()).or_default();
        for (inline, path) in paths_in(&tokens(&text)) {
            let mut here = module.clone();
            here.extend(inline);
            let Some(target) = resolve(&here, &path, modules) else {
                continue;
            };
            let (target_module, name) = target;
            let target_file = &modules[&target_module];
            if target_file != rel {
                edges.entry(target_file.clone()).or_default().insert(name);
            }
        }
    }
    graph
}

/// The file-level module a path names (its longest prefix that is a module file) and the
/// name it takes from there; `None` for paths into other crates.
fn resolve(
    here: &[String],
    path: &[String],
    modules: &BTreeMap<Vec<String>, PathBuf>,
) -> Option<(Vec<String>, String)> {
    let mut abs: Vec<String> = match path.first().map(String::as_str) {
        Some("crate") => Vec::new(),
        Some("self") | Some("super") => here.to_vec(),
        Some(first) => {
            // A child module named without `self::` (2018 paths).
            let mut child = here.to_vec();
            child.push(first.to_string());
            if !modules.contains_key(&child) {
                return None;
            }
            here.to_vec()
        }
        None => return None,
    };
    let mut rest = path;
    while let Some(first) = rest.first() {
        match first.as_str() {
            "crate" | "self" => {}
            "super" => {
                abs.pop();
            }
            _ => break,
        }
        rest = &rest[1..];
    }
    abs.extend(rest.iter().cloned());
    // Inline modules live in their file: walk back to the longest prefix with a file.
    (0..=abs.len()).rev().find_map(|k| {
        let prefix = abs[..k].to_vec();
        modules.contains_key(&prefix).then(|| {
            let name = abs.get(k).cloned().unwrap_or_else(|| "*".to_string());
            (prefix, name)
        })
    })
}

/// The source without comments, strings and character literals, as identifiers and
/// single punctuation characters (`::` kept as one token).
fn tokens(text: &str) -> Vec<String> {
    let c: Vec<char> = text.chars().collect();
    let mut out = Vec::new();
    let mut i = 0;
    while i < c.len() {
        let ch = c[i];
        if ch == '/' && c.get(i + 1) == Some(&'/') {
            while i < c.len() && c[i] != '\n' {
                i += 1;
            }
        } else if ch == '/' && c.get(i + 1) == Some(&'*') {
            let mut depth = 0;
            while i < c.len() {
                if c[i] == '/' && c.get(i + 1) == Some(&'*') {
                    depth += 1;
                    i += 2;
                } else if c[i] == '*' && c.get(i + 1) == Some(&'/') {
                    depth -= 1;
                    i += 2;
                    if depth == 0 {
                        break;
                    }
                } else {
                    i += 1;
                }
            }
        } else if ch == 'r'
            && matches!(c.get(i + 1), Some('"') | Some('#'))
            && raw_string(&c, i).is_some()
        {
            i = raw_string(&c, i).unwrap_or(i + 1);
        } else if ch == '"' {
            i += 1;
            while i < c.len() && c[i] != '"' {
                i += if c[i] == '\\' { 2 } else { 1 };
            }
            i += 1;
        } else if ch == '\'' {
            // A character literal ('x', '\n', '\u{..}') or a lifetime ('a).
            if c.get(i + 1) == Some(&'\\') {
                i += 2;
                while i < c.len() && c[i] != '\'' {
                    i += 1;
                }
                i += 1;
            } else if c.get(i + 2) == Some(&'\'') {
                i += 3;
            } else {
                i += 1;
            }
        } else if ch.is_alphabetic() || ch == '_' {
            let start = i;
            while i < c.len() && (c[i].is_alphanumeric() || c[i] == '_') {
                i += 1;
            }
            out.push(c[start..i].iter().collect());
        } else if ch == ':' && c.get(i + 1) == Some(&':') {
            out.push("::".to_string());
            i += 2;
        } else if ch.is_whitespace() || ch.is_ascii_digit() {
            i += 1;
        } else {
            out.push(ch.to_string());
            i += 1;
        }
    }
    out
}

/// The end of a raw string literal starting at `i` (`r"…"`, `r#"…"#`, …), if it is one.
fn raw_string(c: &[char], i: usize) -> Option<usize> {
    let mut j = i + 1;
    let mut hashes = 0;
    while c.get(j) == Some(&'#') {
        hashes += 1;
        j += 1;
    }
    if c.get(j) != Some(&'"') {
        return None;
    }
    j += 1;
    while j < c.len() {
        if c[j] == '"' && (1..=hashes).all(|k| c.get(j + k) == Some(&'#')) {
            return Some(j + 1 + hashes);
        }
        j += 1;
    }
    Some(c.len())
}

/// Every path of the tokens (`a::b::c`, and `use` trees expanded) with the inline modules
/// it is written in; items under `#[cfg(test)]` are skipped. Paths into other crates come
/// along too: [`resolve`] drops them. A re-export (`pub use`, `pub(crate) use`) counts only
/// when the file's own code uses the name: otherwise it is the module's face, not a
/// dependency of its code.
fn paths_in(t: &[String]) -> Vec<(Vec<String>, Vec<String>)> {
    let mut out = Vec::new();
    let mut reexports = Vec::new();
    let mut used: BTreeSet<&str> = BTreeSet::new();
    let mut inline: Vec<(String, usize)> = Vec::new();
    let mut depth = 0usize;
    let mut i = 0;
    while i < t.len() {
        let tok = t[i].as_str();
        if tok == "#" && is_cfg_test(t, i) {
            // Skip the attribute, any further attributes, then the item.
            i = skip_attributes(t, i);
            i = skip_item(t, i);
            continue;
        }
        let names = || inline.iter().map(|(n, _)| n.clone()).collect::<Vec<_>>();
        match tok {
            "{" => depth += 1,
            "}" => {
                depth = depth.saturating_sub(1);
                if inline.last().is_some_and(|(_, d)| *d == depth) {
                    inline.pop();
                }
            }
            "mod" if t.get(i + 2).map(String::as_str) == Some("{") => {
                inline.push((t[i + 1].clone(), depth));
                depth += 1;
                i += 3;
                continue;
            }
            "use" => {
                let end = (i..t.len()).find(|&k| t[k] == ";").unwrap_or(t.len());
                let mut paths = Vec::new();
                use_tree(&t[i + 1..end], &[], &mut paths);
                let here = names();
                let paths = paths.into_iter().map(|p| (here.clone(), p));
                if is_reexport(t, i) {
                    reexports.extend(paths);
                } else {
                    out.extend(paths.map(|(h, (p, _))| (h, p)));
                }
                i = end + 1;
                continue;
            }
            s if is_ident(s) => {
                used.insert(s);
                let continued = i > 0 && t[i - 1] == "::";
                if !continued && t.get(i + 1).map(String::as_str) == Some("::") {
                    let mut path = vec![tok.to_string()];
                    let mut k = i + 1;
                    while t.get(k).map(String::as_str) == Some("::")
                        && t.get(k + 1).is_some_and(|s| is_ident(s))
                    {
                        path.push(t[k + 1].clone());
                        used.insert(&t[k + 1]);
                        k += 2;
                    }
                    out.push((names(), path));
                    i = k;
                    continue;
                }
            }
            _ => {}
        }
        i += 1;
    }
    out.extend(
        reexports
            .into_iter()
            .filter(|(_, (_, local))| used.contains(local.as_str()))
            .map(|(h, (p, _))| (h, p)),
    );
    out
}

/// The `use` at `i` is preceded by a visibility (`pub`, `pub(crate)`, `pub(super)`, …).
fn is_reexport(t: &[String], i: usize) -> bool {
    match i.checked_sub(1).map(|k| t[k].as_str()) {
        Some("pub") => true,
        Some(")") => (1..=4).any(|k| i > k && t[i - k - 1] == "pub" && t[i - k] == "("),
        _ => false,
    }
}

fn is_ident(s: &str) -> bool {
    s.chars()
        .next()
        .is_some_and(|c| c.is_alphabetic() || c == '_')
}

/// `#[cfg(test)]` starts at `i`.
fn is_cfg_test(t: &[String], i: usize) -> bool {
    let want = ["#", "[", "cfg", "(", "test", ")", "]"];
    t.len() >= i + want.len() && want.iter().enumerate().all(|(k, w)| t[i + k] == *w)
}

/// The index after the attributes (`#[…]`, nested brackets included) that start at `i`.
fn skip_attributes(t: &[String], mut i: usize) -> usize {
    while t.get(i).map(String::as_str) == Some("#") && t.get(i + 1).map(String::as_str) == Some("[")
    {
        let mut level = 0;
        i += 1;
        while i < t.len() {
            match t[i].as_str() {
                "[" => level += 1,
                "]" => {
                    level -= 1;
                    if level == 0 {
                        i += 1;
                        break;
                    }
                }
                _ => {}
            }
            i += 1;
        }
    }
    i
}

/// The index after the item that starts at `i`: up to a `;` outside braces, or to the
/// brace that closes its body.
fn skip_item(t: &[String], mut i: usize) -> usize {
    let mut level = 0;
    while i < t.len() {
        match t[i].as_str() {
            ";" if level == 0 => return i + 1,
            "{" => level += 1,
            "}" => {
                level -= 1;
                if level == 0 {
                    return i + 1;
                }
            }
            _ => {}
        }
        i += 1;
    }
    i
}

/// Expands a `use` tree (`a::{b, c::{d, self}, e as f, *}`) into paths, each with the
/// name it brings into scope (`*` for a glob).
fn use_tree(t: &[String], prefix: &[String], out: &mut Vec<(Vec<String>, String)>) {
    // Split the tree at top-level commas.
    let mut level = 0;
    let mut start = 0;
    let mut parts = Vec::new();
    for (k, tok) in t.iter().enumerate() {
        match tok.as_str() {
            "{" => level += 1,
            "}" => level -= 1,
            "," if level == 0 => {
                parts.push(&t[start..k]);
                start = k + 1;
            }
            _ => {}
        }
    }
    parts.push(&t[start..]);
    for part in parts {
        let mut path = prefix.to_vec();
        let mut local = None;
        let mut k = 0;
        while k < part.len() {
            match part[k].as_str() {
                "::" | "pub" => k += 1,
                "{" => {
                    let close = part.iter().rposition(|s| s == "}").unwrap_or(part.len());
                    use_tree(&part[k + 1..close], &path, out);
                    path.clear();
                    break;
                }
                "as" => {
                    local = part.get(k + 1).cloned();
                    break;
                }
                "*" => {
                    local = Some("*".to_string());
                    break;
                }
                "self" if !path.is_empty() => k += 1,
                s if is_ident(s) => {
                    path.push(s.to_string());
                    k += 1;
                }
                _ => k += 1,
            }
        }
        if let Some(last) = path.last().cloned() {
            out.push((path, local.unwrap_or(last)));
        }
    }
}

/// The circles of the graph (strongly connected components of two or more files), each
/// written out with the names that tie it.
fn cycles(graph: &Graph) -> Vec<(BTreeSet<PathBuf>, String)> {
    let nodes: Vec<&PathBuf> = graph.keys().collect();
    let index: BTreeMap<&PathBuf, usize> = nodes.iter().enumerate().map(|(k, n)| (*n, k)).collect();
    let succ: Vec<Vec<usize>> = nodes
        .iter()
        .map(|n| {
            graph[*n]
                .keys()
                .filter_map(|m| index.get(m).copied())
                .collect()
        })
        .collect();
    // Tarjan's algorithm, iterative.
    let n = nodes.len();
    let (mut idx, mut low, mut on) = (vec![usize::MAX; n], vec![0; n], vec![false; n]);
    let (mut stack, mut comps, mut counter) = (Vec::new(), Vec::new(), 0);
    for root in 0..n {
        if idx[root] != usize::MAX {
            continue;
        }
        let mut work = vec![(root, 0usize)];
        while let Some(&mut (v, ref mut next)) = work.last_mut() {
            if *next == 0 && idx[v] == usize::MAX {
                idx[v] = counter;
                low[v] = counter;
                counter += 1;
                stack.push(v);
                on[v] = true;
            }
            if let Some(&w) = succ[v].get(*next) {
                *next += 1;
                if idx[w] == usize::MAX {
                    work.push((w, 0));
                } else if on[w] {
                    low[v] = low[v].min(idx[w]);
                }
                continue;
            }
            work.pop();
            if let Some(&(parent, _)) = work.last() {
                low[parent] = low[parent].min(low[v]);
            }
            if low[v] == idx[v] {
                let mut comp = Vec::new();
                while let Some(w) = stack.pop() {
                    on[w] = false;
                    comp.push(w);
                    if w == v {
                        break;
                    }
                }
                if comp.len() > 1 {
                    comps.push(comp);
                }
            }
        }
    }
    comps
        .into_iter()
        .map(|comp| {
            let members: BTreeSet<usize> = comp.into_iter().collect();
            let mut lines = vec![format!(
                "circle of {}:",
                members
                    .iter()
                    .map(|&k| nodes[k].display().to_string())
                    .collect::<Vec<_>>()
                    .join(", ")
            )];
            for &a in &members {
                for (b, names) in &graph[nodes[a]] {
                    if index.get(b).is_some_and(|k| members.contains(k)) {
                        lines.push(format!(
                            "  {} -> {}: {}",
                            nodes[a].display(),
                            b.display(),
                            names.iter().cloned().collect::<Vec<_>>().join(", ")
                        ));
                    }
                }
            }
            let files = members.iter().map(|&k| nodes[k].clone()).collect();
            (files, lines.join("\n"))
        })
        .collect()
}
