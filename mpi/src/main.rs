//! `pdcontact-mpi`: the `pdcontact` command line ([`pdcontact::cli`]) built with the system's
//! MPI library. Started by `mpirun` as several processes, `pdcontact run` and
//! `pdcontact bench --lattice-sphere` are decomposed over them (docs/guide/mpi.md); started
//! once, it runs as `pdcontact` does.

use std::sync::Arc;

use pdcontact::parallel::Comm;

mod comm;

fn main() -> std::process::ExitCode {
    pdcontact::cli::main(Some(|| {
        comm::MpiComm::initialize()
            .map(|c| Arc::new(c) as Arc<dyn Comm>)
            .ok_or_else(|| "it was initialised before in this process".to_string())
    }))
}
