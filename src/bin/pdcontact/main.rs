//! `pdcontact`: the command line ([`pdcontact::cli`]) in one process, on every core through
//! threads. Its MPI build is the `pdcontact-mpi` package.

fn main() -> std::process::ExitCode {
    pdcontact::cli::main(None)
}
