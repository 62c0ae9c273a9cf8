//! One name per idea across the commands: the names, and the older names
//! each still takes as a hidden alias (parsed, never shown in a help).

use clap::CommandFactory;

/// Command, the name shown, the older name it also takes, and the words
/// that make the rest of the command line valid.
const RENAMED: &[(&str, &str, &str, &str)] = &[
    ("probe plan", "--safe-z", "--z-safe", "--origin 0,0 --count 2,2 --pitch 1 --plunge 5 --safe-z 5 -o o.nc"),
    ("probe plan", "--program-number", "--program", "--origin 0,0 --count 2,2 --pitch 1 --plunge 5 --safe-z 5 -o o.nc"),
    ("thermal plan", "--program-number", "--number", ""),
    ("probe mill", "--res", "--resolution", "d.txt --stylus ball:2 --tool ball:2 -o o.nc"),
    ("probe mill", "--gouge-tol", "--tolerance", "d.txt --stylus ball:2 --tool ball:2 -o o.nc"),
    ("mill", "--gouge-tol", "--tolerance", "s.stl --tool ball:2 --stepover 1"),
    ("relief", "--leave-tol", "--tolerance", "p.png --width 20 --depth 1 --tool ball:2 --stepover 1"),
    ("sim", "--profile", "--tool-profile", "p.nc --res 1"),
    ("view", "--profile", "--tool-profile", "p.nc"),
    ("scallop", "--cusp", "--target", "--tool ball:6 --angle 30"),
    ("run", "--to", "--emit", "p.nc"),
    ("texture", "--to", "--emit", "p.nc --seed 7"),
    ("thermal apply", "--to", "--emit", "p.nc --model m.json"),
    ("wear apply", "--to", "--emit", "p.nc --profile t.csv --nominal ball:1 --surface s.stl"),
    ("convert", "--to", "--emit", "p.nc"),
    ("demo", "--output", "--out", "--only relief"),
    ("mill", "--sample-step", "--step", "s.stl --tool ball:2 --stepover 1"),
    ("relief", "--sample-step", "--step", "p.png --width 20 --depth 1 --tool ball:2 --stepover 1"),
    ("probe mill", "--sample-step", "--step", "d.txt --stylus ball:2 --tool ball:2 -o o.nc"),
    ("engage", "--next-pass", "--step", ENGAGE),
    ("engage", "--rotation-steps", "--steps", ENGAGE),
    ("wear apply", "--tool-name", "--tool-id", "p.nc --nominal ball:1 --surface s.stl"),
];

/// The words `engage` needs.
const ENGAGE: &str = "--tool ball:6 --angle 30 --pick-feed 0.5 --depth 0.5 --feed-per-tooth 0.1";

/// A value each renamed option takes.
fn value(option: &str) -> &'static str {
    match option {
        "--to" => "linuxcnc",
        "--profile" => "t.csv",
        "--program-number" => "2000",
        "--next-pass" => "both",
        "--rotation-steps" => "360",
        "--tool-name" => "T7",
        "--output" => "demo",
        _ => "0.01",
    }
}

fn parses(words: &[String]) -> Result<(), String> {
    kezuri::Cli::command().try_get_matches_from(words).map(|_| ()).map_err(|e| e.to_string())
}

fn help(path: &str) -> String {
    let mut command = kezuri::Cli::command();
    command.build();
    let mut c = &mut command;
    for name in path.split(' ') {
        c = c.find_subcommand_mut(name).unwrap();
    }
    c.render_long_help().to_string()
}

#[test]
fn old_names_are_hidden_aliases_of_the_new() {
    for (command, new, old, rest) in RENAMED {
        let line = |option: &str| -> Vec<String> {
            let mut words = vec!["kezuri".to_string()];
            words.extend(command.split(' ').map(str::to_string));
            // The renamed option in the rest takes the name tried.
            words.extend(rest.split_whitespace().map(|w| if w == *new { option } else { w }.to_string()));
            if !rest.split_whitespace().any(|w| w == *new) {
                words.extend([option.to_string(), value(new).to_string()]);
            }
            words
        };
        parses(&line(new)).unwrap_or_else(|e| panic!("{command} {new}: {e}"));
        parses(&line(old)).unwrap_or_else(|e| panic!("{command} {old}: {e}"));
        let help = help(command);
        assert!(help.contains(&format!("{new} <")), "{command} --help shows {new}:\n{help}");
        let shown =
            help.lines().any(|l| l.trim_start().starts_with(&format!("{old} ")) || l.contains(&format!("{old},")));
        assert!(!shown, "{command} --help shows the older {old}:\n{help}");
    }
}

#[test]
fn one_name_per_option_idea() {
    // The names given up are nowhere in any help, as options.
    let mut all = String::new();
    fn walk(c: &mut clap::Command, out: &mut String) {
        out.push_str(&c.render_long_help().to_string());
        let names: Vec<String> = c.get_subcommands().map(|s| s.get_name().to_string()).collect();
        for n in names {
            walk(c.find_subcommand_mut(&n).unwrap(), out);
        }
    }
    let mut command = kezuri::Cli::command();
    command.build();
    walk(&mut command, &mut all);
    for old in ["--z-safe", "--resolution", "--tool-profile", "--target", "--emit", "--tolerance", "--number <"] {
        assert!(!all.contains(old), "a help still names {old}");
    }
}

/// Every help: its command path and its long help.
fn every_help() -> Vec<(String, String)> {
    fn walk(c: &mut clap::Command, path: &str, out: &mut Vec<(String, String)>) {
        out.push((path.to_string(), c.render_long_help().to_string()));
        let names: Vec<String> = c.get_subcommands().map(|s| s.get_name().to_string()).collect();
        for n in names.into_iter().filter(|n| n != "help") {
            let p = if path.is_empty() { n.clone() } else { format!("{path} {n}") };
            walk(c.find_subcommand_mut(&n).unwrap(), &p, out);
        }
    }
    let mut command = kezuri::Cli::command();
    command.build();
    let mut out = Vec::new();
    walk(&mut command, "", &mut out);
    out
}

/// The options a help declares: (short, long name, its description).
fn declared(help: &str) -> Vec<(Option<char>, String, String)> {
    let mut out: Vec<(Option<char>, String, String)> = Vec::new();
    let (mut open, mut options) = (false, false);
    for line in help.lines() {
        // The options section: from `Options:` to the next line that is not indented.
        if !line.is_empty() && !line.starts_with(' ') {
            options = line == "Options:";
            continue;
        }
        if !options {
            continue;
        }
        let t = line.trim_start();
        let (short, rest) = match t.strip_prefix('-') {
            Some(r) if r.chars().nth(1) == Some(',') => (r.chars().next(), r[2..].trim_start()),
            _ => (None, t),
        };
        if line.starts_with("  ") && rest.starts_with("--") {
            let name: String = rest.chars().take_while(|c| !c.is_whitespace()).collect();
            let text = rest[name.len()..].trim_start();
            // The value's name, then (in a short help) the description.
            let text = if text.starts_with('<') { text.split_once('>').map_or("", |t| t.1) } else { text };
            out.push((short, name, text.trim().to_string()));
            open = true;
        } else if t.is_empty() {
            open = matches!(out.last(), Some(o) if o.2.is_empty());
        } else if open {
            let last = out.last_mut().unwrap();
            last.2 = format!("{} {}", last.2, t).trim().to_string();
        }
    }
    out
}

#[test]
fn each_option_name_means_one_thing_in_every_help() {
    let helps = every_help();
    let options: Vec<(String, Option<char>, String, String)> = helps
        .iter()
        .flat_map(|(path, help)| declared(help).into_iter().map(move |(s, n, d)| (path.clone(), s, n, d)))
        .collect();
    let commands_with =
        |name: &str| -> Vec<&str> { options.iter().filter(|o| o.2 == name).map(|o| o.0.as_str()).collect::<Vec<_>>() };
    // `--step` meant a sampling step in mill and a side of the pass in engage.
    for gone in ["--step", "--steps", "--tool-id", "--out"] {
        let left: Vec<&str> =
            commands_with(gone).into_iter().filter(|c| *c != "thermal plan" || gone != "--steps").collect();
        assert!(left.is_empty(), "{gone} is still an option of {left:?}");
    }
    assert_eq!(commands_with("--sample-step"), ["mill", "probe mill", "relief"]);
    for o in options.iter().filter(|o| o.2 == "--sample-step") {
        assert!(o.3.starts_with("Sampling step along a row"), "{} --sample-step: {}", o.0, o.3);
    }
    // A tool number (T<n>) has one name.
    assert_eq!(commands_with("--tool-number"), ["mill", "probe plan", "probe mill", "thermal plan"]);
    for o in &options {
        let d = o.3.to_lowercase();
        if d.contains("tool number") || d.contains("tool's number") {
            assert_eq!(o.2, "--tool-number", "{}: {} names a tool number: {}", o.0, o.2, o.3);
        }
    }
    // A tool in the tool database goes by its name.
    assert_eq!(commands_with("--tool-name"), ["wear apply"]);
    for (path, help) in &helps {
        assert!(!help.contains("TOOL_ID") && !help.contains("TOOL-ID"), "{path} --help:\n{help}");
    }
    for path in ["tool db add", "tool db show"] {
        let help = &helps.iter().find(|h| h.0 == path).unwrap().1;
        assert!(help.contains("<TOOL_NAME>"), "{path} --help:\n{help}");
    }
    // Every output file is -o, --output; the demo's folder too.
    for o in options.iter().filter(|o| o.2 == "--output") {
        assert_eq!(o.1, Some('o'), "{} --output without -o", o.0);
    }
    assert!(commands_with("--output").contains(&"demo"));
    // The simulation's cell size has a default, said.
    for path in ["sim", "view"] {
        let res = options.iter().find(|o| o.0 == path && o.2 == "--res").unwrap();
        assert!(res.3.contains("[default: a tenth of the smallest cutter's radius"), "{path} --res: {}", res.3);
    }
}

/// A help's prose: without its usage line, option names and value names.
fn prose(help: &str) -> String {
    let mut text = String::new();
    let mut usage = false;
    for line in help.lines() {
        if line.starts_with("Usage:") {
            usage = true;
        } else if line.trim().is_empty() {
            usage = false;
        }
        if !usage {
            text.push_str(line.trim());
            text.push(' ');
        }
    }
    let (mut out, mut chars) = (String::new(), text.chars().peekable());
    while let Some(c) = chars.next() {
        if c == '-' && chars.peek() == Some(&'-') {
            while chars.peek().is_some_and(|c| c.is_ascii_alphanumeric() || *c == '-') {
                chars.next();
            }
        } else if c == '<' {
            for c in chars.by_ref() {
                if c == '>' {
                    break;
                }
            }
        } else {
            out.extend(c.to_lowercase());
        }
    }
    out
}

/// The part of `s` from byte `a` to byte `b`, widened to whole characters.
fn around(s: &str, mut a: usize, mut b: usize) -> &str {
    b = b.min(s.len());
    while !s.is_char_boundary(a) {
        a -= 1;
    }
    while !s.is_char_boundary(b) {
        b += 1;
    }
    &s[a..b]
}

/// Where `word` first stands in `text` as a word of its own (`e_d`, not
/// `angle_deg`).
fn find_word(text: &str, word: &str) -> Option<usize> {
    text.match_indices(word).map(|(i, _)| i).find(|&i| {
        let before = text[..i].chars().next_back();
        !before.is_some_and(|c| c.is_alphanumeric() || c == '_')
    })
}

#[test]
fn jargon_is_explained_where_a_help_first_uses_it() {
    // The word (any of its forms) and what must stand within 250 characters of its first use.
    let jargon: &[(&[&str], &[&str])] = &[
        (&["e_d"], &["times its distance from the axis"]),
        (&["z-map"], &["grid of heights"]),
        (&["cl point"], &["cutter-location"]),
        (&["pick feed", "pick-feed"], &["step from"]),
        (&["cusp"], &["ridge left between", "ridges left between"]),
        (&["drop-cutter"], &["lowered"]),
        (&["sagitta"], &["stray from the arc"]),
    ];
    let mut unexplained = Vec::new();
    for (path, help) in every_help() {
        let text = prose(&help);
        for (words, glosses) in jargon {
            let Some(first) = words.iter().filter_map(|w| find_word(&text, w)).min() else { continue };
            let near = around(&text, first.saturating_sub(250), first + 250);
            if !glosses.iter().any(|g| near.contains(g)) {
                unexplained.push(format!("kezuri {path} --help: {:?} first used unexplained: …{near}…", words[0]));
            }
        }
    }
    assert!(unexplained.is_empty(), "{}", unexplained.join("\n\n"));
}
