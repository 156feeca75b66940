//! The command line from the library's declaration of the commands
//! (`rvlife::api::commands::COMMANDS`): [`cli`] is the parser with each subcommand's
//! description and each option's help taken from the declaration (the derive in `main.rs`
//! gives the parser its types and clap's rules between options). The tests check that every
//! declared command is a subcommand, every option the declaration gives the command line is
//! an argument with the declared default and help, and the parser has nothing the declaration
//! does not name.

use crate::Cli;
use clap::CommandFactory;
use rvlife::api::commands::{Front, COMMANDS};

/// The command line's parser: [`Cli`]'s, each declared subcommand's description
/// (`CommandDecl::about`) and each declared option's help (`OptionDecl::help`) set from the
/// declaration.
pub(crate) fn cli() -> clap::Command {
    COMMANDS.iter().fold(Cli::command(), |cmd, decl| {
        cmd.mut_subcommand(decl.name, |sub| {
            decl.options
                .iter()
                .filter(|o| o.fronts.contains(&Front::Cli))
                .fold(sub.about(decl.about), |sub, o| {
                    sub.mut_arg(o.name, |a| a.help(o.help))
                })
        })
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use rvlife::api::commands::Default;
    use std::collections::BTreeSet;

    /// Arguments every subcommand has that are not the command's options: the config file (a
    /// positional argument), the global work budget, help.
    const NOT_OPTIONS: &[&str] = &["config", "work_budget_min", "help"];

    /// The default clap shows for an argument, as one text (`None`: no default).
    fn clap_default(arg: &clap::Arg) -> Option<String> {
        let v = arg.get_default_values();
        (!v.is_empty()).then(|| {
            v.iter()
                .map(|s| s.to_string_lossy().into_owned())
                .collect::<Vec<_>>()
                .join(",")
        })
    }

    #[test]
    fn every_declared_command_and_option_is_the_command_lines() {
        let cli = cli();
        let declared: BTreeSet<&str> = COMMANDS.iter().map(|c| c.name).collect();
        let parsed: BTreeSet<&str> = cli
            .get_subcommands()
            .map(|s| s.get_name())
            .filter(|n| *n != "help")
            .collect();
        assert_eq!(
            parsed, declared,
            "the subcommands are not the declared commands"
        );
        for decl in COMMANDS {
            let sub = cli.find_subcommand(decl.name).expect("declared above");
            assert_eq!(
                sub.get_about().map(|a| a.to_string()).as_deref(),
                Some(decl.about),
                "rvlife {}: description",
                decl.name
            );
            for arg in sub.get_arguments().filter(|a| a.get_id() != "help") {
                assert!(
                    arg.get_help().is_some_and(|h| !h.to_string().is_empty()),
                    "rvlife {} --{}: no help",
                    decl.name,
                    arg.get_id()
                );
            }
            let args: BTreeSet<&str> = sub
                .get_arguments()
                .map(|a| a.get_id().as_str())
                .filter(|id| !NOT_OPTIONS.contains(id))
                .collect();
            let options: BTreeSet<&str> = decl
                .options
                .iter()
                .filter(|o| o.fronts.contains(&Front::Cli))
                .map(|o| o.name)
                .collect();
            assert_eq!(
                args, options,
                "rvlife {}: arguments and declared options differ",
                decl.name
            );
            for o in decl
                .options
                .iter()
                .filter(|o| o.fronts.contains(&Front::Cli))
            {
                let arg = sub
                    .get_arguments()
                    .find(|a| a.get_id() == o.name)
                    .expect("compared above");
                // A flag's `false` is clap's own, set when the parser is built.
                let shown = clap_default(arg).filter(|d| d != "false");
                let expected = match o.default_in(Front::Cli) {
                    _ if o.name == "out" && decl.out_dir.is_some() => {
                        decl.out_dir.map(str::to_string)
                    }
                    Default::Absent | Default::Required | Default::Off => None,
                    Default::Number(x) => Some(format!("{x}")),
                    Default::Count(n) => Some(n.to_string()),
                    Default::Text(t) => Some(t.to_string()),
                };
                assert_eq!(
                    shown, expected,
                    "rvlife {} --{}: default",
                    decl.name, o.name
                );
                assert!(
                    !o.help.is_empty(),
                    "rvlife {} --{}: no help",
                    decl.name,
                    o.name
                );
                assert_eq!(
                    arg.get_help().map(|h| h.to_string()).as_deref(),
                    Some(o.help),
                    "rvlife {} --{}: help",
                    decl.name,
                    o.name
                );
                if o.default_in(Front::Cli) == Default::Required {
                    assert!(
                        arg.is_required_set(),
                        "rvlife {} --{} is required",
                        decl.name,
                        o.name
                    );
                }
            }
        }
    }
}
