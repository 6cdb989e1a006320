//! The top-level modules of `src/` are layers that import one way: the module graph read from
//! the `crate::` and `super::` paths of their files has no cycle. Unit-test modules
//! (`#[cfg(test)] mod ...`, at the end of a file) are left out: a test may build its fixtures
//! from a higher layer.

use std::collections::{BTreeMap, BTreeSet};
use std::path::Path;

/// Which modules each top-level module imports, and in which of its files: `(from, to)` to the
/// files of `from` that name `to`.
type Imports = BTreeMap<(String, String), BTreeSet<String>>;

/// The top-level modules a file at `path` (relative to `src/`, `/`-separated) names by
/// `crate::` or `super::` paths, outside comments and unit-test modules.
fn imported_modules(path: &str, text: &str) -> BTreeSet<String> {
    // The module the file is: `a.rs` and `a/mod.rs` are `a`, `a/b.rs` is `a::b`.
    let mut module: Vec<&str> = path.trim_end_matches(".rs").split('/').collect();
    if module.last() == Some(&"mod") {
        module.pop();
    }
    let code = text.find("#[cfg(test)]\nmod ").map_or(text, |end| &text[..end]);
    let mut found = BTreeSet::new();
    for line in code.lines().filter(|l| !l.trim_start().starts_with("//")) {
        for (at, _) in line.match_indices("crate::").chain(line.match_indices("super::")) {
            // Only whole path starts: not `foo_crate::` or `self::super::`.
            if line[..at].ends_with(|c: char| c.is_alphanumeric() || c == '_' || c == ':') {
                continue;
            }
            let mut rest = &line[at..];
            let mut depth = module.len();
            if let Some(after) = rest.strip_prefix("crate::") {
                (rest, depth) = (after, 0);
            }
            while let Some(after) = rest.strip_prefix("super::") {
                rest = after;
                depth = depth.saturating_sub(1);
            }
            if depth > 0 {
                continue; // within the same top-level module
            }
            found.extend(first_segments(rest));
        }
    }
    found.remove(module[0]);
    found
}

/// The first segment of a path (`a::b` gives `a`), or of each path in a group (`{a::b, c}`).
fn first_segments(path: &str) -> Vec<String> {
    let ident = |s: &str| -> String {
        s.trim_start().chars().take_while(|c| c.is_alphanumeric() || *c == '_').collect()
    };
    let Some(group) = path.strip_prefix('{') else {
        return vec![ident(path)].into_iter().filter(|s| !s.is_empty()).collect();
    };
    // Split the group at its own commas, not those of nested groups.
    let (mut names, mut depth, mut start) = (Vec::new(), 0, 0);
    for (i, c) in group.char_indices() {
        match c {
            '{' => depth += 1,
            '}' if depth == 0 => {
                names.push(ident(&group[start..i]));
                break;
            }
            '}' => depth -= 1,
            ',' if depth == 0 => {
                names.push(ident(&group[start..i]));
                start = i + 1;
            }
            _ => {}
        }
    }
    names.into_iter().filter(|s| !s.is_empty() && s != "self").collect()
}

fn imports_of(files: &[(String, String)]) -> Imports {
    let mut imports = Imports::new();
    for (path, text) in files {
        let from = path.split('/').next().unwrap().trim_end_matches(".rs").to_string();
        for to in imported_modules(path, text) {
            imports.entry((from.clone(), to)).or_default().insert(path.clone());
        }
    }
    imports
}

/// A cycle of modules (its first repeated at the end), if the import graph has one.
fn find_cycle(imports: &Imports) -> Option<Vec<String>> {
    let mut edges: BTreeMap<&str, Vec<&str>> = BTreeMap::new();
    for (from, to) in imports.keys() {
        edges.entry(from).or_default().push(to);
    }
    // Depth-first search; a module met again while still on the path closes a cycle.
    fn visit<'a>(
        module: &'a str,
        edges: &BTreeMap<&'a str, Vec<&'a str>>,
        path: &mut Vec<&'a str>,
        done: &mut BTreeSet<&'a str>,
    ) -> Option<Vec<String>> {
        if let Some(at) = path.iter().position(|m| *m == module) {
            let mut cycle: Vec<String> = path[at..].iter().map(|m| m.to_string()).collect();
            cycle.push(module.to_string());
            return Some(cycle);
        }
        if !done.insert(module) {
            return None;
        }
        path.push(module);
        for next in edges.get(module).into_iter().flatten() {
            if let Some(cycle) = visit(next, edges, path, done) {
                return Some(cycle);
            }
        }
        path.pop();
        None
    }
    let mut done = BTreeSet::new();
    edges.keys().find_map(|module| visit(module, &edges, &mut Vec::new(), &mut done))
}

/// Every `.rs` file under `src/` but the crate roots, as (path relative to `src/`, text).
fn source_files() -> Vec<(String, String)> {
    fn walk(dir: &Path, root: &Path, files: &mut Vec<(String, String)>) {
        for entry in std::fs::read_dir(dir).unwrap() {
            let path = entry.unwrap().path();
            if path.is_dir() {
                walk(&path, root, files);
            } else if path.extension().is_some_and(|e| e == "rs") {
                let relative =
                    path.strip_prefix(root).unwrap().to_string_lossy().replace('\\', "/");
                if relative != "lib.rs" && relative != "main.rs" {
                    files.push((relative, std::fs::read_to_string(&path).unwrap()));
                }
            }
        }
    }
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let mut files = Vec::new();
    walk(&root, &root, &mut files);
    files.sort();
    files
}

/// The cycle, each step with the files that make it.
fn describe(cycle: &[String], imports: &Imports) -> String {
    cycle
        .windows(2)
        .map(|step| {
            let files = &imports[&(step[0].clone(), step[1].clone())];
            format!("{} imports {} in {:?}", step[0], step[1], files)
        })
        .collect::<Vec<_>>()
        .join("; ")
}

#[test]
fn top_level_modules_import_one_way() {
    let files = source_files();
    assert!(files.len() > 50, "the sources were found ({} files)", files.len());
    let imports = imports_of(&files);
    let mutual: Vec<String> = imports
        .iter()
        .filter(|((from, to), _)| from < to && imports.contains_key(&(to.clone(), from.clone())))
        .map(|((from, to), files)| {
            let back = &imports[&(to.clone(), from.clone())];
            format!("{from} <-> {to}: {from} in {files:?}, {to} in {back:?}")
        })
        .collect();
    assert!(mutual.is_empty(), "modules that import each other:\n{}", mutual.join("\n"));
    if let Some(cycle) = find_cycle(&imports) {
        panic!("an import cycle: {}", describe(&cycle, &imports));
    }
}

/// The reader and the search on made-up files: grouped and `super::` paths, comments and unit
/// tests left out, a cycle through three modules found.
#[test]
fn a_cycle_through_three_modules_is_found() {
    let file = |path: &str, text: &str| (path.to_string(), text.to_string());
    let files = [
        file("a/mod.rs", "use crate::{b::{X, Y}, a::Z};\n// crate::c in a comment\n"),
        file("a/deep.rs", "use super::super::d::W;\n#[cfg(test)]\nmod tests { use crate::e; }\n"),
        file("b.rs", "fn f() -> c::T { crate::c::T::new() }\n"),
        file("c.rs", "use super::a::Q;\n"),
        file("d.rs", "use std::fmt;\n"),
    ];
    let imports = imports_of(&files);
    let edges: Vec<(&str, &str)> =
        imports.keys().map(|(from, to)| (from.as_str(), to.as_str())).collect();
    assert_eq!(edges, [("a", "b"), ("a", "d"), ("b", "c"), ("c", "a")]);
    let cycle = find_cycle(&imports).expect("a -> b -> c -> a");
    assert_eq!(cycle, ["a", "b", "c", "a"]);
    assert!(describe(&cycle, &imports).contains(r#"c imports a in {"c.rs"}"#));
}
