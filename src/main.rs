fn main() {
    std::process::exit(spar::cli::main());
}
