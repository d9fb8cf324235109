//! The README promises two set-up commands; CI must run the test one
//! verbatim, or a green CI proves nothing about what users run.

fn readme_commands() -> Vec<String> {
    let readme = include_str!("../../README.md");
    let block = readme
        .split("```sh\n")
        .nth(1)
        .and_then(|rest| rest.split("```").next())
        .expect("README has a ```sh block");
    block
        .lines()
        .map(|l| l.split('#').next().unwrap().trim().to_string())
        .filter(|l| !l.is_empty())
        .collect()
}

#[test]
fn readme_opens_with_two_commands_and_ci_runs_the_test_one() {
    let commands = readme_commands();
    assert_eq!(commands.len(), 2, "{commands:?}");
    assert!(commands[0].contains("render"), "{commands:?}");
    assert!(commands[1].contains("cargo test"), "{commands:?}");
    let ci = include_str!("../../.ci/run");
    assert!(
        ci.lines().any(|l| l.trim() == commands[1]),
        ".ci/run does not run the README's test command `{}` verbatim",
        commands[1]
    );
    assert!(ci.contains("apt-get update"));
}
