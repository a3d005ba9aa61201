//! The README and the guide (docs/*.md) as a reader meets them on a forge: every heading the README had before
//! the guide was made still has a home, every relative link and anchor leads somewhere, the README and each
//! page link to each other, and every shell example runs as written, with the validation layer on.
//!
//! tests/docs/readme-headings.txt is the README's headings when it was split into the guide, made with
//! `git show 34ff1b2:README.md | awk '/^[ ]*```/{f=!f; next} !f && /^#/'` (lines starting with '#' inside a
//! fence are a shell's comments, not headings).

mod common;

use std::collections::{BTreeSet, HashMap};
use std::os::unix::fs::PermissionsExt;
use std::os::unix::process::CommandExt;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

use common::root;

/// The files a reader reads: README.md, then every docs/*.md by name.
fn documents() -> Vec<PathBuf> {
    let mut pages: Vec<PathBuf> = std::fs::read_dir(root().join("docs"))
        .expect("docs/")
        .map(|entry| entry.expect("an entry of docs/").path())
        .filter(|path| path.extension().is_some_and(|e| e == "md"))
        .collect();
    pages.sort();
    assert!(!pages.is_empty(), "docs/ holds no page");
    std::iter::once(root().join("README.md")).chain(pages).collect()
}

/// A file's name as the messages give it: relative to the repository.
fn shown(path: &Path) -> String {
    path.strip_prefix(root()).unwrap_or(path).display().to_string()
}

/// A fenced code block: where its fence is, its language, its text (less the fence's indentation) and, when the
/// line just before the fence is `<!-- not run: REASON -->`, the reason.
struct Block {
    line: usize,
    language: String,
    text: String,
    not_run: Option<String>,
}

/// A Markdown file taken apart the way the tests need it.
struct Document {
    path: PathBuf,
    /// ATX headings outside code blocks, their text without the '#'s, in order.
    headings: Vec<String>,
    blocks: Vec<Block>,
    /// The text with code blocks, inline code and HTML comments blanked out (newlines kept, so that offsets
    /// still give line numbers): what remains is where links can be.
    prose: String,
    /// `<!-- not run: ... -->` lines followed by something other than a shell block, by line.
    stray_not_run: Vec<usize>,
}

fn not_run_reason(line: &str) -> Option<String> {
    let inner = line.trim().strip_prefix("<!-- not run:")?.strip_suffix("-->")?;
    Some(inner.trim().to_string())
}

fn parse(path: &Path) -> Document {
    let text = std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", shown(path)));
    let lines: Vec<&str> = text.split('\n').collect();
    let mut headings = Vec::new();
    let mut blocks = Vec::new();
    let mut prose_lines: Vec<String> = Vec::new();
    let mut stray_not_run = Vec::new();
    // The open block: its fence's indentation and backticks, and the block so far.
    let mut open: Option<(usize, String, Block)> = None;
    for (index, line) in lines.iter().enumerate() {
        let trimmed = line.trim_start();
        let indent = line.len() - trimmed.len();
        if let Some((fence_indent, fence, block)) = open.as_mut() {
            if trimmed.trim_end() == fence.as_str() {
                blocks.push(open.take().unwrap().2);
            } else {
                let cut = line.len() - line.trim_start_matches(' ').len();
                block.text.push_str(&line[cut.min(*fence_indent)..]);
                block.text.push('\n');
            }
            prose_lines.push(String::new());
            continue;
        }
        if trimmed.starts_with("```") {
            let fence: String = trimmed.chars().take_while(|&c| c == '`').collect();
            let language = trimmed[fence.len()..].split_whitespace().next().unwrap_or("").to_string();
            let not_run = index.checked_sub(1).and_then(|before| not_run_reason(lines[before]));
            open = Some((indent, fence, Block { line: index + 1, language, text: String::new(), not_run }));
            prose_lines.push(String::new());
            continue;
        }
        if not_run_reason(line).is_some() {
            let next = lines.get(index + 1).map_or("", |l| l.trim_start());
            if !next.starts_with("```sh") {
                stray_not_run.push(index + 1);
            }
        }
        if line.starts_with('#') {
            let level = line.chars().take_while(|&c| c == '#').count();
            if level <= 6 && line[level..].starts_with(' ') {
                headings.push(line[level..].trim().to_string());
            }
        }
        prose_lines.push(line.to_string());
    }
    assert!(open.is_none(), "{}: a code block is never closed", shown(path));
    let prose = blank_out(&prose_lines.join("\n"));
    Document { path: path.to_path_buf(), headings, blocks, prose, stray_not_run }
}

/// Blanks inline code spans and HTML comments, keeping newlines.
fn blank_out(text: &str) -> String {
    let blank = |s: &str| s.chars().map(|c| if c == '\n' { '\n' } else { ' ' }).collect::<String>();
    let mut out = String::with_capacity(text.len());
    let mut rest = text;
    while !rest.is_empty() {
        if let Some(after) = rest.strip_prefix("<!--") {
            let end = after.find("-->").map_or(after.len(), |e| e + 3);
            out.push_str(&blank(&rest[..4 + end]));
            rest = &after[end..];
        } else if rest.starts_with('`') {
            let run = rest.chars().take_while(|&c| c == '`').count();
            let fence = &rest[..run];
            // The span closes at the next run of exactly as many backticks.
            let mut closing = None;
            let mut from = run;
            while let Some(found) = rest[from..].find(fence) {
                let at = from + found;
                let longer = rest[at + run..].starts_with('`');
                if !longer {
                    closing = Some(at);
                    break;
                }
                from = at + rest[at..].chars().take_while(|&c| c == '`').count();
            }
            match closing {
                Some(at) => {
                    out.push_str(&blank(&rest[..at + run]));
                    rest = &rest[at + run..];
                }
                None => {
                    out.push_str(fence);
                    rest = &rest[run..];
                }
            }
        } else {
            let c = rest.chars().next().unwrap();
            out.push(c);
            rest = &rest[c.len_utf8()..];
        }
    }
    out
}

/// GitHub's anchor for a heading: lower case, spaces to '-', punctuation (backticks, colons, apostrophes,
/// dots, ...) dropped, letters of any script, digits, '-' and '_' kept.
fn slug(heading: &str) -> String {
    heading
        .to_lowercase()
        .chars()
        .filter_map(|c| match c {
            ' ' => Some('-'),
            '-' | '_' => Some(c),
            c if c.is_alphanumeric() => Some(c),
            _ => None,
        })
        .collect()
}

/// Every anchor of a document: each heading's slug, a repeated one with -1, -2, ... as GitHub numbers them.
fn anchors(document: &Document) -> BTreeSet<String> {
    let mut seen: HashMap<String, usize> = HashMap::new();
    let mut anchors = BTreeSet::new();
    for heading in &document.headings {
        let base = slug(heading);
        let count = seen.entry(base.clone()).or_insert(0);
        anchors.insert(if *count == 0 { base.clone() } else { format!("{base}-{count}") });
        *count += 1;
    }
    anchors
}

/// The targets of `[text](target)` and `![alt](target)` in the prose, with their line numbers.
fn links(document: &Document) -> Vec<(usize, String)> {
    let prose = &document.prose;
    let mut found = Vec::new();
    let mut from = 0;
    while let Some(at) = prose[from..].find("](") {
        let start = from + at + 2;
        let end = prose[start..].find(')').map_or(prose.len(), |e| start + e);
        let target = prose[start..end].split_whitespace().next().unwrap_or("").to_string();
        let line = prose[..start].matches('\n').count() + 1;
        found.push((line, target));
        from = end;
    }
    found
}

#[test]
fn every_heading_of_the_old_readme_has_a_home() {
    let list = std::fs::read_to_string(root().join("tests/docs/readme-headings.txt")).unwrap();
    let old: Vec<&str> = list.lines().map(|l| l.trim_start_matches('#').trim()).filter(|l| !l.is_empty()).collect();
    assert!(old.len() >= 30, "the list holds {} headings", old.len());
    let mut homes: HashMap<String, Vec<String>> = HashMap::new();
    for document in documents().iter().map(|p| parse(p)) {
        for heading in &document.headings {
            homes.entry(heading.clone()).or_default().push(shown(&document.path));
        }
    }
    let homeless: Vec<&&str> = old.iter().filter(|h| !homes.contains_key(**h)).collect();
    assert!(
        homeless.is_empty(),
        "headings of the old README that are no heading of README.md or docs/*.md: {homeless:?}"
    );
}

#[test]
fn every_link_leads_somewhere_and_the_pages_link_both_ways() {
    let documents: Vec<Document> = documents().iter().map(|p| parse(p)).collect();
    let anchors_of: HashMap<PathBuf, BTreeSet<String>> =
        documents.iter().map(|d| (d.path.canonicalize().unwrap(), anchors(d))).collect();
    let readme = root().join("README.md").canonicalize().unwrap();
    let mut broken = Vec::new();
    let mut targets_of: HashMap<PathBuf, BTreeSet<PathBuf>> = HashMap::new();
    for document in &documents {
        let name = shown(&document.path);
        let folder = document.path.parent().unwrap();
        for (line, target) in links(document) {
            if target.is_empty() {
                broken.push(format!("{name}:{line}: an empty link"));
                continue;
            }
            if target.starts_with("http://") || target.starts_with("https://") || target.starts_with("mailto:") {
                continue;
            }
            let (file, anchor) = match target.split_once('#') {
                Some((file, anchor)) => (file, Some(anchor)),
                None => (target.as_str(), None),
            };
            let path = if file.is_empty() { document.path.clone() } else { folder.join(file) };
            let Ok(path) = path.canonicalize() else {
                broken.push(format!("{name}:{line}: {target}: no such file"));
                continue;
            };
            if let Some(anchor) = anchor {
                match anchors_of.get(&path) {
                    Some(anchors) if anchors.contains(anchor) => {}
                    Some(_) => broken.push(format!("{name}:{line}: {target}: no heading makes #{anchor} there")),
                    None => broken.push(format!("{name}:{line}: {target}: an anchor into a file that is not a page")),
                }
            }
            targets_of.entry(document.path.canonicalize().unwrap()).or_default().insert(path);
        }
        for line in &document.stray_not_run {
            broken.push(format!("{name}:{line}: a `not run` comment that is not just before a ```sh block"));
        }
    }
    let empty = BTreeSet::new();
    for document in &documents[1..] {
        let page = document.path.canonicalize().unwrap();
        if !targets_of.get(&readme).unwrap_or(&empty).contains(&page) {
            broken.push(format!("README.md does not link to {}", shown(&document.path)));
        }
        if !targets_of.get(&page).unwrap_or(&empty).contains(&readme) {
            broken.push(format!("{} does not link back to README.md", shown(&document.path)));
        }
    }
    assert!(broken.is_empty(), "{}", broken.join("\n"));
}

/// Splits a shell line into words as sh would for plain quoting (no expansions), up to a comment.
fn words(line: &str) -> Vec<String> {
    let mut words = Vec::new();
    let mut word: Option<String> = None;
    let mut chars = line.chars();
    while let Some(c) = chars.next() {
        match c {
            '\'' | '"' => {
                let text = word.get_or_insert_with(String::new);
                for q in chars.by_ref() {
                    if q == c {
                        break;
                    }
                    text.push(q);
                }
            }
            '#' if word.is_none() => break,
            c if c.is_whitespace() => words.extend(word.take()),
            c => word.get_or_insert_with(String::new).push(c),
        }
    }
    words.extend(word);
    words
}

/// The files a block's commands say they write (`-o`, `--output`, `--ids`, `--chart`, `--screenshot`).
fn files_written(script: &str) -> Vec<String> {
    let joined = script.replace("\\\n", " ");
    let mut files = Vec::new();
    for line in joined.lines() {
        let words = words(line);
        for pair in words.windows(2) {
            if ["-o", "--output", "--ids", "--chart", "--screenshot"].contains(&pair[0].as_str()) {
                files.push(pair[1].clone());
            }
        }
    }
    files
}

/// Runs `script` with `sh -e -x` in `folder`, with `bin` first on PATH; gives up (the test fails) after
/// `limit`, killing the script and everything it started.
fn run_script(script: &str, folder: &Path, bin: &Path, limit: Duration) -> (bool, String) {
    let path = format!("{}:{}", bin.display(), std::env::var("PATH").unwrap_or_default());
    let mut child = Command::new("sh")
        .args(["-e", "-x", "-c", script])
        .current_dir(folder)
        .env("PATH", path)
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .process_group(0)
        .spawn()
        .expect("sh");
    let deadline = Instant::now() + limit;
    let out = common::read_on_a_thread(child.stdout.take().unwrap());
    let err = common::read_on_a_thread(child.stderr.take().unwrap());
    let status = loop {
        if let Some(status) = child.try_wait().expect("wait for sh") {
            break Some(status);
        }
        if Instant::now() > deadline {
            // SAFETY: the group is the one this function made for the script; killing it kills nothing else.
            unsafe { libc::killpg(child.id() as libc::pid_t, libc::SIGKILL) };
            let _ = child.wait();
            break None;
        }
        std::thread::sleep(Duration::from_millis(20));
    };
    let text = |reader: std::thread::JoinHandle<Vec<u8>>| String::from_utf8_lossy(&reader.join().unwrap()).into_owned();
    let output = format!("{}{}", text(out), text(err));
    match status {
        Some(status) => (status.success(), format!("{status}\n{output}")),
        None => (false, format!("still running after {limit:?}: killed\n{output}")),
    }
}

#[test]
fn every_shell_example_runs_as_written() {
    // `vk-render` on PATH is the binary under test with the validation layer on, as every test runs it
    // (common::vk_render): it has no environment variable for it, so a two-line script adds `--validate`, and any
    // message of the layer makes the command, and so the example, fail.
    let bin = common::temp_dir();
    let wrapper = bin.path().join("vk-render");
    std::fs::write(&wrapper, format!("#!/bin/sh\nexec '{}' --validate \"$@\"\n", env!("CARGO_BIN_EXE_vk-render")))
        .unwrap();
    std::fs::set_permissions(&wrapper, std::fs::Permissions::from_mode(0o755)).unwrap();
    let mut failures = Vec::new();
    let mut run = 0;
    let mut skipped = Vec::new();
    let started = Instant::now();
    for document in documents().iter().map(|p| parse(p)) {
        let name = shown(&document.path);
        for block in &document.blocks {
            if ["bash", "shell", "console", "zsh", "shell-session"].contains(&block.language.as_str()) {
                failures.push(format!("{name}:{}: a shell example is written ```sh, so that it is run", block.line));
                continue;
            }
            if block.language != "sh" {
                continue;
            }
            if let Some(reason) = &block.not_run {
                if reason.is_empty() {
                    failures.push(format!("{name}:{}: `not run` without its reason", block.line));
                }
                skipped.push(format!("{name}:{}: {reason}", block.line));
                continue;
            }
            // A fresh folder holding what the examples read by relative path: the scenes, assets and test scenes.
            let folder = common::temp_dir();
            std::os::unix::fs::symlink(root().join("assets"), folder.path().join("assets")).unwrap();
            std::fs::create_dir(folder.path().join("tests")).unwrap();
            std::os::unix::fs::symlink(root().join("tests/scenes"), folder.path().join("tests/scenes")).unwrap();
            let began = Instant::now();
            // A hang's deadline: the longest example takes 23 s alone, more on a busy machine.
            let (ok, output) = run_script(&block.text, folder.path(), bin.path(), Duration::from_secs(600));
            eprintln!("{name}:{}: {:.1} s", block.line, began.elapsed().as_secs_f64());
            run += 1;
            if !ok {
                failures.push(format!("{name}:{}: the example failed: {output}", block.line));
                continue;
            }
            for file in files_written(&block.text) {
                if !folder.path().join(&file).exists() {
                    failures
                        .push(format!("{name}:{}: the example says it writes {file}, which is not there", block.line));
                }
            }
        }
    }
    eprintln!(
        "{run} shell examples run in {:.1} s; not run:\n  {}",
        started.elapsed().as_secs_f64(),
        skipped.join("\n  ")
    );
    assert!(run >= 10, "only {run} shell examples found to run");
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

#[test]
fn the_parser_and_the_slugs_follow_github() {
    assert_eq!(slug("Analytic BRDFs: BRDF Explorer's `.brdf` files"), "analytic-brdfs-brdf-explorers-brdf-files");
    assert_eq!(slug("For a course's staff: `vk-render serve`"), "for-a-courses-staff-vk-render-serve");
    assert_eq!(slug("Scene files (format version 1)"), "scene-files-format-version-1");
    assert_eq!(slug("What the profile showed, and what was done"), "what-the-profile-showed-and-what-was-done");
    let folder = common::temp_dir();
    let page = folder.path().join("page.md");
    let text = "# A\n\n```sh\n# a comment, not a heading\nvk-render x -o 'a b.png' # -o c.png\n```\n\n## A\n\n\
                see `[no](link)` and [yes](#a-1)\n<!-- not run: why -->\n  ```sh\n  echo\n  ```\n";
    std::fs::write(&page, text).unwrap();
    let document = parse(&page);
    assert_eq!(document.headings, ["A", "A"]);
    assert_eq!(anchors(&document), BTreeSet::from(["a".to_string(), "a-1".to_string()]));
    assert_eq!(links(&document), [(10, "#a-1".to_string())]);
    assert_eq!(document.blocks.len(), 2);
    assert_eq!(document.blocks[1].not_run.as_deref(), Some("why"));
    assert_eq!(document.blocks[1].text, "echo\n");
    assert_eq!(files_written(&document.blocks[0].text), ["a b.png"]);
}
