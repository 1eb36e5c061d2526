//! [`Comm`] on the system's MPI through rsmpi.

use mpi::datatype::{Partition, PartitionMut};
use mpi::environment::Universe;
use mpi::topology::SimpleCommunicator;
use mpi::traits::*;
use mpi::Count;

use pdcontact::parallel::Comm;

/// The world communicator of an initialised MPI environment, which it owns: MPI is finalised
/// when the last reference to it is dropped.
pub struct MpiComm {
    world: SimpleCommunicator,
    _universe: Universe,
}

// SAFETY: MPI is initialised with the default threading level and every call is made from the
// main thread: rayon's workers never hold the communicator (the model calls it between its
// parallel passes). Send + Sync only let the model, which is shared with those workers by
// reference, carry it.
unsafe impl Send for MpiComm {}
unsafe impl Sync for MpiComm {}

impl MpiComm {
    /// MPI initialised, and its world communicator; `None` where MPI was initialised
    /// before (once a process).
    pub fn initialize() -> Option<MpiComm> {
        let universe = mpi::initialize()?;
        Some(MpiComm {
            world: universe.world(),
            _universe: universe,
        })
    }
}

fn displacements(counts: &[Count]) -> Vec<Count> {
    counts
        .iter()
        .scan(0, |at, &c| {
            let d = *at;
            *at += c;
            Some(d)
        })
        .collect()
}

impl Comm for MpiComm {
    fn rank(&self) -> usize {
        self.world.rank() as usize
    }

    fn size(&self) -> usize {
        self.world.size() as usize
    }

    fn all_gather(&self, mine: &[f64]) -> Vec<f64> {
        let mut out = vec![0.0; mine.len() * self.size()];
        self.world.all_gather_into(mine, &mut out[..]);
        out
    }

    fn all_gather_varcount(&self, mine: &[f64]) -> Vec<Vec<f64>> {
        let (flat, counts) = self.all_gather_flat(mine);
        let counts: Vec<Count> = counts.iter().map(|&c| c as Count).collect();
        split(&flat, &counts)
    }

    fn all_gather_flat(&self, mine: &[f64]) -> (Vec<f64>, Vec<usize>) {
        let n = self.size();
        let mut counts = vec![0 as Count; n];
        self.world
            .all_gather_into(&(mine.len() as Count), &mut counts[..]);
        let displs = displacements(&counts);
        let total = counts.iter().map(|&c| c as usize).sum();
        let mut flat = vec![0.0; total];
        {
            let mut part = PartitionMut::new(&mut flat[..], &counts[..], &displs[..]);
            self.world.all_gather_varcount_into(mine, &mut part);
        }
        (flat, counts.iter().map(|&c| c as usize).collect())
    }

    fn exchange(&self, send: &[Vec<f64>]) -> Vec<Vec<f64>> {
        let n = self.size();
        let send_counts: Vec<Count> = send.iter().map(|v| v.len() as Count).collect();
        let mut recv_counts = vec![0 as Count; n];
        self.world
            .all_to_all_into(&send_counts[..], &mut recv_counts[..]);
        let flat_send: Vec<f64> = send.concat();
        let send_displs = displacements(&send_counts);
        let recv_displs = displacements(&recv_counts);
        let total = recv_counts.iter().map(|&c| c as usize).sum();
        let mut flat = vec![0.0; total];
        {
            let out = Partition::new(&flat_send[..], &send_counts[..], &send_displs[..]);
            let mut into = PartitionMut::new(&mut flat[..], &recv_counts[..], &recv_displs[..]);
            self.world.all_to_all_varcount_into(&out, &mut into);
        }
        split(&flat, &recv_counts)
    }

    fn abort(&self, code: i32) -> ! {
        self.world.abort(code)
    }
}

fn split(flat: &[f64], counts: &[Count]) -> Vec<Vec<f64>> {
    let mut at = 0;
    counts
        .iter()
        .map(|&c| {
            let v = flat[at..at + c as usize].to_vec();
            at += c as usize;
            v
        })
        .collect()
}
