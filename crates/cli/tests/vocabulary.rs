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
];

/// A value each renamed option takes.
fn value(option: &str) -> &'static str {
    match option {
        "--to" => "linuxcnc",
        "--profile" => "t.csv",
        "--program-number" => "2000",
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
