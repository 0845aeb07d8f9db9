//! The guide held to the rules the code is held to: no page over 700 lines, no history of the
//! project's own making (a session, an issue or a turn given its number), and every page named in
//! the architecture page and pulled into `guide/mod.rs`. The history check reads the code's
//! comments and README.md as well.

use std::collections::BTreeSet;
use std::path::{Path, PathBuf};

const ARCHITECTURE: &str = include_str!("architecture.md");
const GUIDE_MOD: &str = include_str!("mod.rs");

/// Longest page, lines: the cap the source files keep.
const MAX_PAGE_LINES: usize = 700;

/// Words a page may not use of the project's history when a number names which one.
const HISTORY_WORDS: &[&str] = &["session", "sessions", "issue", "issues", "turn", "turns"];

const NUMBER_WORDS: [&str; 20] = [
    "one",
    "two",
    "three",
    "four",
    "five",
    "six",
    "seven",
    "eight",
    "nine",
    "ten",
    "eleven",
    "twelve",
    "thirteen",
    "fourteen",
    "fifteen",
    "sixteen",
    "seventeen",
    "eighteen",
    "nineteen",
    "twenty",
];

const ORDINAL_WORDS: [&str; 22] = [
    "first",
    "second",
    "third",
    "fourth",
    "fifth",
    "sixth",
    "seventh",
    "eighth",
    "ninth",
    "tenth",
    "eleventh",
    "twelfth",
    "thirteenth",
    "fourteenth",
    "fifteenth",
    "sixteenth",
    "seventeenth",
    "eighteenth",
    "nineteenth",
    "twentieth",
    "last",
    "previous",
];

fn guide_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("src/guide")
}

/// Every page of the guide: its file name and text.
fn pages() -> Vec<(String, String)> {
    let mut out: Vec<(String, String)> = std::fs::read_dir(guide_dir())
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "md"))
        .map(|p| {
            let name = p.file_name().unwrap().to_string_lossy().to_string();
            (name, std::fs::read_to_string(&p).unwrap())
        })
        .collect();
    out.sort();
    out
}

fn is_number(word: &str) -> bool {
    let digits = word.trim_start_matches('#');
    (!digits.is_empty() && digits.chars().all(|c| c.is_ascii_digit()))
        || NUMBER_WORDS.contains(&word)
}

fn is_ordinal(word: &str) -> bool {
    ORDINAL_WORDS.contains(&word)
        || ["st", "nd", "rd", "th"]
            .iter()
            .any(|s| word.strip_suffix(s).is_some_and(is_number))
}

/// The places in `text` where a history word is counted (next to a number or after an
/// ordinal), or repeated with "by" between: `(line, the words)`.
pub(crate) fn history_mentions(text: &str) -> Vec<(usize, String)> {
    let mut out = Vec::new();
    for (n, line) in text.lines().enumerate() {
        let words: Vec<String> = line
            .split(|c: char| !(c.is_alphanumeric() || c == '#'))
            .filter(|w| !w.is_empty())
            .map(str::to_lowercase)
            .collect();
        for (i, w) in words.iter().enumerate() {
            if !HISTORY_WORDS.contains(&w.as_str()) {
                continue;
            }
            let before = i.checked_sub(1).map(|j| words[j].as_str());
            let after = words.get(i + 1).map(String::as_str);
            // "turn" counts only after an ordinal: "0 turns it off", "a facet turns 10°" are
            // geometry and switches; an ordinal before it numbers a turn of the work.
            let counted = if w.starts_with("turn") {
                before.is_some_and(|b| is_ordinal(b) && b != "last")
            } else {
                before.is_some_and(|b| is_ordinal(b) || is_number(b))
                    || after.is_some_and(is_number)
                    || (after == Some("by") && words.get(i + 2) == Some(w))
            };
            if counted {
                let from = i.saturating_sub(1);
                out.push((n + 1, words[from..(i + 2).min(words.len())].join(" ")));
            }
        }
    }
    out
}

#[test]
fn no_guide_page_is_over_the_line_cap() {
    let long: Vec<(String, usize)> = pages()
        .into_iter()
        .map(|(name, text)| (name, text.lines().count()))
        .filter(|&(_, n)| n > MAX_PAGE_LINES)
        .collect();
    assert!(
        long.is_empty(),
        "guide pages over {MAX_PAGE_LINES} lines: {long:?}"
    );
}

#[test]
fn the_guide_keeps_no_history_of_its_making() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let mut texts = pages();
    texts.push((
        "README.md".into(),
        std::fs::read_to_string(root.join("README.md")).unwrap(),
    ));
    // The code's comments too.
    let mut files = BTreeSet::new();
    for dir in ["src", "tests"] {
        super::tests::rust_files(root, &root.join(dir), &mut files);
    }
    for name in files {
        let text = std::fs::read_to_string(root.join(&name)).unwrap();
        texts.push((name, text));
    }
    let found: Vec<String> = texts
        .iter()
        .flat_map(|(name, text)| {
            history_mentions(text)
                .into_iter()
                .map(move |(line, words)| format!("{name}:{line}: \"{words}\""))
        })
        .collect();
    assert!(
        found.is_empty(),
        "the guide speaks of the program, not of its making; history found:\n{}",
        found.join("\n")
    );
}

#[test]
fn the_history_check_tells_history_from_use() {
    // The history words are filled in here, so that this file tells no history itself.
    let fill = |t: &str| {
        t.replace("<s>", "session")
            .replace("<i>", "issue")
            .replace("<t>", "turn")
    };
    for history in [
        "as <s> twelve found",
        "the third <s>",
        "see <i> 26",
        "<i> #27 asks",
        "over the last two <s>s' runs",
        "measured <s> by <s>",
        "in the second <t>",
    ] {
        let history = fill(history);
        assert_eq!(history_mentions(&history).len(), 1, "{history}");
    }
    for use_ in [
        "the rows of a session are written under",
        "sessions older than 7 days",
        "the yarns turn, none is compressed",
        "taken in turn (standard, fine)",
        "the explorer's session folder",
        "a quarter turn",
        "0 turns it off",
        "a facet turns 10° at an edge",
    ] {
        assert!(history_mentions(use_).is_empty(), "{use_}");
    }
}

#[test]
fn every_guide_page_is_named_in_the_architecture_page_and_pulled_in() {
    let on_disk: BTreeSet<String> = pages().into_iter().map(|(name, _)| name).collect();
    let named: BTreeSet<String> = ARCHITECTURE
        .split('`')
        .skip(1)
        .step_by(2)
        .filter_map(|s| s.strip_prefix("guide/"))
        .filter(|s| s.ends_with(".md"))
        .map(str::to_string)
        .collect();
    let included: BTreeSet<String> = GUIDE_MOD
        .split("include_str!(\"")
        .skip(1)
        .filter_map(|s| s.split('"').next())
        .map(str::to_string)
        .collect();
    let unnamed: Vec<_> = on_disk.difference(&named).collect();
    let gone: Vec<_> = named.difference(&on_disk).collect();
    let not_pulled: Vec<_> = on_disk.difference(&included).collect();
    assert!(
        unnamed.is_empty() && gone.is_empty() && not_pulled.is_empty(),
        "guide pages not named in architecture.md: {unnamed:?}; named there but gone: {gone:?}; \
         not pulled into guide/mod.rs: {not_pulled:?}"
    );
}
