//! The MPI transport (rsmpi 0.8), one process per rank. Variable-size
//! buffers travel by `gather_varcount` after a gather of their lengths
//! (notes §2.2). A panic on any rank calls `MPI_Abort`, so that the other
//! ranks do not wait forever in a collective (notes §2.5, pitfall 6).

use std::cell::Cell;

use mpi::datatype::PartitionMut;
use mpi::topology::SimpleCommunicator;
use mpi::traits::*;
use mpi::Count;

use crate::{Gathered, Transport};

pub struct Mpi {
    _universe: mpi::environment::Universe,
    world: SimpleCommunicator,
    sent: Cell<u64>,
}

impl Mpi {
    /// Initialises MPI (funneled: only the main thread calls MPI; faer's
    /// threads do not). Returns `None` if MPI was initialised already.
    pub fn init() -> Option<Self> {
        let (universe, _) = mpi::initialize_with_threading(mpi::Threading::Funneled)?;
        let world = universe.world();
        let rank = world.rank();
        let default_hook = std::panic::take_hook();
        std::panic::set_hook(Box::new(move |info| {
            default_hook(info);
            eprintln!("rank {rank} panicked: aborting every rank");
            // SAFETY: MPI is initialised; MPI_Abort on the world communicator ends all ranks.
            unsafe {
                mpi::ffi::MPI_Abort(mpi::ffi::RSMPI_COMM_WORLD, 3);
            }
        }));
        Some(Self {
            _universe: universe,
            world,
            sent: Cell::new(0),
        })
    }

    /// How many ranks share this rank's machine (MPI_COMM_TYPE_SHARED).
    pub fn ranks_on_this_node(&self) -> usize {
        self.world.split_shared(self.world.rank()).size() as usize
    }

    /// True when this process was started by an MPI launcher.
    pub fn launched() -> bool {
        [
            "OMPI_COMM_WORLD_SIZE",
            "PMI_SIZE",
            "PMIX_RANK",
            "MPI_LOCALNRANKS",
        ]
        .iter()
        .any(|v| std::env::var_os(v).is_some())
    }
}

impl Transport for Mpi {
    fn rank(&self) -> usize {
        self.world.rank() as usize
    }
    fn size(&self) -> usize {
        self.world.size() as usize
    }
    fn gather_bytes(&self, local: Vec<u8>) -> Option<Gathered> {
        let root = self.world.process_at_rank(0);
        let n = local.len() as Count;
        if self.rank() != 0 {
            self.sent.set(self.sent.get() + local.len() as u64 + 4);
        }
        if self.rank() == 0 {
            let mut counts = vec![0 as Count; self.size()];
            root.gather_into_root(&n, &mut counts[..]);
            let displs: Vec<Count> = counts
                .iter()
                .scan(0, |acc, &c| {
                    let d = *acc;
                    *acc += c;
                    Some(d)
                })
                .collect();
            let total: Count = counts.iter().sum();
            let mut buf = vec![0u8; total as usize];
            {
                let mut part = PartitionMut::new(&mut buf[..], &counts[..], &displs[..]);
                root.gather_varcount_into_root(&local[..], &mut part);
            }
            drop(local);
            Some(Gathered {
                bytes: buf,
                counts: counts.iter().map(|&c| c as usize).collect(),
            })
        } else {
            root.gather_into(&n);
            root.gather_varcount_into(&local[..]);
            None
        }
    }
    fn broadcast_bytes(&self, data: Option<&[u8]>) -> Vec<u8> {
        let root = self.world.process_at_rank(0);
        let mut bytes = if self.rank() == 0 {
            data.unwrap_or_default().to_vec()
        } else {
            Vec::new()
        };
        let mut len = bytes.len() as u64;
        root.broadcast_into(&mut len);
        bytes.resize(len as usize, 0);
        root.broadcast_into(&mut bytes[..]);
        if self.rank() == 0 {
            self.sent
                .set(self.sent.get() + len * (self.size() as u64 - 1));
        }
        bytes
    }
    fn abort(&self, code: i32) -> ! {
        self.world.abort(code)
    }
    fn bytes_sent(&self) -> u64 {
        self.sent.get()
    }
    fn kind(&self) -> &'static str {
        "mpi"
    }
}
