fn main() -> std::process::ExitCode {
    sweetspot::cli::main()
}
