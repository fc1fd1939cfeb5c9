fn main() {
    std::process::exit(glint::cli::main());
}
