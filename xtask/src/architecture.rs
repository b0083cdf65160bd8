//! `cargo xtask check-architecture`: the workspace's crate graph must equal the one written in
//! `docs/architecture.md`.
//!
//! The documented graph is the fenced code block with the info string `crate-graph`. Each
//! non-empty line that is not a `#` comment reads `CRATE: DEP DEP ...` (package names; nothing
//! after the colon for a crate without workspace dependencies). Every workspace member appears
//! exactly once. The compared edges are a member's normal and build dependencies on other
//! workspace members, as `cargo metadata` reports them; dev-dependencies are ignored.

use std::collections::{BTreeMap, BTreeSet};
use std::path::Path;

use anyhow::{Context, Result, bail};
use serde_json::Value;

/// The documented graph's file, relative to the workspace root.
pub const DOC: &str = "docs/architecture.md";

/// Crate (package name) → the workspace crates it depends on.
pub type Graph = BTreeMap<String, BTreeSet<String>>;

/// Checks the workspace against [`DOC`]; prints one line on success, every difference on failure.
pub fn run(root: &Path) -> Result<()> {
    let doc_path = root.join(DOC);
    let markdown = std::fs::read_to_string(&doc_path)
        .with_context(|| format!("could not read {}", doc_path.display()))?;
    let doc = parse_doc(&markdown).with_context(|| format!("{DOC}: bad `crate-graph` block"))?;
    let output = crate::cargo()
        .args(["metadata", "--format-version", "1", "--no-deps"])
        .output()
        .context("could not run `cargo metadata`")?;
    if !output.status.success() {
        bail!(
            "`cargo metadata` failed with {}:\n{}",
            output.status,
            String::from_utf8_lossy(&output.stderr)
        );
    }
    let metadata = std::str::from_utf8(&output.stdout).context("`cargo metadata` output")?;
    let workspace = parse_metadata(metadata)?;
    let problems = compare(&doc, &workspace);
    if !problems.is_empty() {
        for p in &problems {
            eprintln!("check-architecture: {p}");
        }
        bail!(
            "check-architecture: {} difference(s) between the workspace and {DOC} \
             (fix the Cargo.toml files or the `crate-graph` block)",
            problems.len()
        );
    }
    let edges: usize = workspace.values().map(BTreeSet::len).sum();
    println!(
        "check-architecture: {} crates, {edges} edges match {DOC}",
        workspace.len()
    );
    Ok(())
}

/// A fence line (```` ``` ```` or `~~~`, at least three): its character, length and info string.
fn fence(line: &str) -> Option<(char, usize, &str)> {
    let trimmed = line.trim_start();
    let c = trimmed.chars().next().filter(|c| matches!(c, '`' | '~'))?;
    let len = trimmed.len() - trimmed.trim_start_matches(c).len();
    (len >= 3).then(|| (c, len, trimmed[len..].trim()))
}

/// The lines inside the single `crate-graph` fenced block, with their 1-based line numbers.
fn graph_block(markdown: &str) -> Result<Vec<(usize, &str)>> {
    // Each `crate-graph` block: its first line and its lines.
    let mut blocks: Vec<(usize, Vec<(usize, &str)>)> = Vec::new();
    // The open fence: character, length, is a `crate-graph` block.
    let mut open: Option<(char, usize, bool)> = None;
    for (i, line) in markdown.lines().enumerate() {
        let number = i + 1;
        match (open, fence(line)) {
            (None, Some((c, len, info))) => {
                let wanted = info.split_whitespace().next() == Some("crate-graph");
                if wanted {
                    blocks.push((number, Vec::new()));
                }
                open = Some((c, len, wanted));
            }
            (Some((c, len, _)), Some((close, close_len, ""))) if close == c && close_len >= len => {
                open = None;
            }
            (Some((_, _, true)), _) => {
                if let Some((_, lines)) = blocks.last_mut() {
                    lines.push((number, line));
                }
            }
            _ => {}
        }
    }
    if let (Some((_, _, true)), Some((start, _))) = (open, blocks.last()) {
        bail!("the `crate-graph` block opened on line {start} is never closed");
    }
    match blocks.len() {
        0 => bail!("no fenced code block with the info string `crate-graph`"),
        1 => Ok(blocks.pop().map(|(_, lines)| lines).unwrap_or_default()),
        n => {
            let starts: Vec<String> = blocks.iter().map(|(s, _)| s.to_string()).collect();
            bail!(
                "{n} `crate-graph` blocks (lines {}); keep exactly one",
                starts.join(", ")
            )
        }
    }
}

/// Parses the `crate-graph` block of `markdown`. Reports every malformed or duplicated line.
pub fn parse_doc(markdown: &str) -> Result<Graph> {
    let mut graph = Graph::new();
    let mut first_line: BTreeMap<String, usize> = BTreeMap::new();
    let mut problems = Vec::new();
    for (number, line) in graph_block(markdown)? {
        let content = line.split('#').next().unwrap_or("").trim();
        if content.is_empty() {
            continue;
        }
        let Some((name, deps)) = content.split_once(':') else {
            problems.push(format!(
                "line {number}: expected `CRATE: DEP DEP ...`, got `{content}`"
            ));
            continue;
        };
        let name = name.trim();
        if name.is_empty() || name.contains(char::is_whitespace) {
            problems.push(format!("line {number}: bad crate name `{name}`"));
            continue;
        }
        if let Some(first) = first_line.get(name) {
            problems.push(format!(
                "line {number}: crate `{name}` is listed again (first on line {first})"
            ));
            continue;
        }
        first_line.insert(name.to_string(), number);
        let mut set = BTreeSet::new();
        for dep in deps.split_whitespace() {
            if !set.insert(dep.to_string()) {
                problems.push(format!("line {number}: `{name}` lists `{dep}` twice"));
            }
        }
        graph.insert(name.to_string(), set);
    }
    if !problems.is_empty() {
        bail!("{}", problems.join("\n"));
    }
    Ok(graph)
}

/// The workspace's graph from `cargo metadata --format-version 1 --no-deps` JSON: each member's
/// normal and build dependencies that are workspace members (dev-dependencies ignored).
pub fn parse_metadata(json: &str) -> Result<Graph> {
    let metadata: Value = serde_json::from_str(json).context("`cargo metadata` is not JSON")?;
    let member_ids: BTreeSet<&str> = metadata["workspace_members"]
        .as_array()
        .context("`cargo metadata`: no `workspace_members` array")?
        .iter()
        .filter_map(Value::as_str)
        .collect();
    let packages = metadata["packages"]
        .as_array()
        .context("`cargo metadata`: no `packages` array")?;
    let members: Vec<&Value> = packages
        .iter()
        .filter(|p| p["id"].as_str().is_some_and(|id| member_ids.contains(id)))
        .collect();
    let names: BTreeSet<&str> = members.iter().filter_map(|p| p["name"].as_str()).collect();
    let mut graph = Graph::new();
    for package in members {
        let name = package["name"]
            .as_str()
            .context("`cargo metadata`: a package without a name")?;
        let deps = package["dependencies"]
            .as_array()
            .with_context(|| format!("`cargo metadata`: `{name}` has no `dependencies` array"))?
            .iter()
            .filter(|d| matches!(d["kind"].as_str(), None | Some("build")))
            .filter_map(|d| d["name"].as_str())
            .filter(|d| names.contains(d))
            .map(str::to_string)
            .collect();
        graph.insert(name.to_string(), deps);
    }
    Ok(graph)
}

/// Every difference between the documented graph and the workspace's, one sentence each.
pub fn compare(doc: &Graph, workspace: &Graph) -> Vec<String> {
    let mut problems = Vec::new();
    for name in doc.keys().filter(|n| !workspace.contains_key(*n)) {
        problems.push(format!(
            "`{name}` is in {DOC} but is not a workspace member"
        ));
    }
    for name in workspace.keys().filter(|n| !doc.contains_key(*n)) {
        problems.push(format!("workspace member `{name}` is missing from {DOC}"));
    }
    for (name, actual) in workspace {
        let Some(documented) = doc.get(name) else {
            continue;
        };
        for dep in actual.difference(documented) {
            problems.push(format!(
                "`{name}` depends on `{dep}` in its Cargo.toml, but {DOC} does not list it"
            ));
        }
        for dep in documented.difference(actual) {
            problems.push(format!(
                "`{name}`: {DOC} lists `{dep}`, but its Cargo.toml has no such (normal or build) dependency"
            ));
        }
    }
    problems
}

#[cfg(test)]
mod tests {
    use super::*;

    const DOC_OK: &str = "# Title\n\n```\nnot: the graph\n```\n\n```crate-graph\n\
        # comment\na: b c\n\nb: c   # trailing comment\nc:\n```\n\ntext\n";

    fn graph(edges: &[(&str, &[&str])]) -> Graph {
        edges
            .iter()
            .map(|(n, d)| (n.to_string(), d.iter().map(|s| s.to_string()).collect()))
            .collect()
    }

    #[test]
    fn parses_the_block_only() {
        let g = parse_doc(DOC_OK).unwrap();
        assert_eq!(g, graph(&[("a", &["b", "c"]), ("b", &["c"]), ("c", &[])]));
        assert!(compare(&g, &g).is_empty());
    }

    #[test]
    fn missing_block_unclosed_block_and_two_blocks_are_errors() {
        assert!(parse_doc("```\na: b\n```\n").is_err());
        assert!(parse_doc("```crate-graph\na: b\n").is_err());
        let two = format!("{DOC_OK}\n```crate-graph\nd:\n```\n");
        assert!(parse_doc(&two).is_err());
    }

    #[test]
    fn malformed_line_is_an_error() {
        let err = parse_doc("```crate-graph\na b\n```\n").unwrap_err();
        assert!(format!("{err:#}").contains("line 2"), "{err:#}");
    }

    #[test]
    fn duplicated_crate_is_an_error() {
        let err = parse_doc("```crate-graph\na: b\nb:\na:\n```\n").unwrap_err();
        let msg = format!("{err:#}");
        assert!(
            msg.contains("`a` is listed again (first on line 2)"),
            "{msg}"
        );
    }

    #[test]
    fn edge_in_cargo_but_not_in_doc_is_reported() {
        let doc = graph(&[("a", &["b"]), ("b", &[]), ("c", &[])]);
        let ws = graph(&[("a", &["b", "c"]), ("b", &[]), ("c", &[])]);
        let problems = compare(&doc, &ws);
        assert_eq!(problems.len(), 1, "{problems:?}");
        assert!(problems[0].contains("`a` depends on `c`"), "{problems:?}");
    }

    #[test]
    fn edge_in_doc_but_not_in_cargo_is_reported() {
        let doc = graph(&[("a", &["b", "c"]), ("b", &[]), ("c", &[])]);
        let ws = graph(&[("a", &["b"]), ("b", &[]), ("c", &[])]);
        let problems = compare(&doc, &ws);
        assert_eq!(problems.len(), 1, "{problems:?}");
        assert!(problems[0].contains("lists `c`"), "{problems:?}");
    }

    #[test]
    fn missing_and_unknown_crates_are_reported() {
        let doc = graph(&[("a", &[]), ("gone", &[])]);
        let ws = graph(&[("a", &[]), ("new", &[])]);
        let problems = compare(&doc, &ws);
        assert_eq!(problems.len(), 2, "{problems:?}");
        assert!(problems[0].contains("`gone` is in"), "{problems:?}");
        assert!(
            problems[1].contains("member `new` is missing"),
            "{problems:?}"
        );
    }

    #[test]
    fn metadata_keeps_normal_and_build_deps_on_members_only() {
        let json = r#"{
          "workspace_members": ["a-id", "b-id", "c-id"],
          "packages": [
            {"id": "a-id", "name": "a", "dependencies": [
              {"name": "b", "kind": null},
              {"name": "c", "kind": "dev"},
              {"name": "serde", "kind": null}
            ]},
            {"id": "b-id", "name": "b", "dependencies": [
              {"name": "c", "kind": "build"},
              {"name": "c", "kind": null}
            ]},
            {"id": "c-id", "name": "c", "dependencies": []}
          ]
        }"#;
        let g = parse_metadata(json).unwrap();
        assert_eq!(g, graph(&[("a", &["b"]), ("b", &["c"]), ("c", &[])]));
    }
}
