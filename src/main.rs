fn main() {
    // First, before any code that may use instructions this CPU lacks.
    spar::cpu::exit_if_unsupported();
    std::process::exit(spar::cli::main());
}
