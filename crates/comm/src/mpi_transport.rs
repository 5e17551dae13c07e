//! The MPI transport (rsmpi 0.8), one process per rank. Variable-size
//! buffers travel by `gather_varcount` after a gather of their lengths
//! (docs/architecture.md, "Libraries"). A panic on any rank calls `MPI_Abort`, so that the other
//! ranks do not wait forever in a collective (docs/architecture.md, "Libraries").

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

/// Where each of consecutive pieces of lengths `counts` starts.
fn offsets<T: Copy + Default + std::ops::Add<Output = T>>(counts: &[T]) -> Vec<T> {
    counts
        .iter()
        .scan(T::default(), |acc, &c| {
            let start = *acc;
            *acc = *acc + c;
            Some(start)
        })
        .collect()
}

/// The most bytes one rank sends in one collective when `ranks` ranks take
/// part: the sum over ranks must fit MPI's 32-bit counts and displacements.
/// `SIGNORINI_MPI_CHUNK_BYTES` lowers it (for testing the rounds).
fn chunk_bytes(ranks: usize) -> usize {
    let limit = (i32::MAX as usize) / ranks.max(1);
    std::env::var("SIGNORINI_MPI_CHUNK_BYTES")
        .ok()
        .and_then(|v| v.parse::<usize>().ok())
        .filter(|&c| c > 0)
        .map_or(limit, |c| c.min(limit))
}

impl Transport for Mpi {
    fn rank(&self) -> usize {
        self.world.rank() as usize
    }
    fn size(&self) -> usize {
        self.world.size() as usize
    }
    /// In rounds of at most [`chunk_bytes`] per rank, so that no count or
    /// displacement of `MPI_Gatherv` (32-bit) overflows: a rank's buffer may
    /// exceed 2 GiB.
    fn gather_bytes(&self, local: Vec<u8>) -> Option<Gathered> {
        let root = self.world.process_at_rank(0);
        let n = local.len() as u64;
        if self.rank() != 0 {
            self.sent.set(self.sent.get() + n + 8);
        }
        let mut lengths = vec![0u64; if self.rank() == 0 { self.size() } else { 0 }];
        if self.rank() == 0 {
            root.gather_into_root(&n, &mut lengths[..]);
        } else {
            root.gather_into(&n);
        }
        let mut longest = lengths.iter().copied().max().unwrap_or(0);
        root.broadcast_into(&mut longest);
        let chunk = chunk_bytes(self.size());
        let rounds = longest.div_ceil(chunk as u64) as usize;
        let piece = |r: usize, len: usize| (r * chunk).min(len)..((r + 1) * chunk).min(len);
        if self.rank() != 0 {
            for r in 0..rounds {
                root.gather_varcount_into(&local[piece(r, local.len())]);
            }
            return None;
        }
        let counts: Vec<usize> = lengths.iter().map(|&c| c as usize).collect();
        let starts = offsets(&counts);
        let mut buf = vec![0u8; counts.iter().sum()];
        for r in 0..rounds {
            let sizes: Vec<Count> = counts.iter().map(|&c| piece(r, c).len() as Count).collect();
            let displs = offsets(&sizes);
            let mut round = vec![0u8; sizes.iter().map(|&c| c as usize).sum()];
            {
                let mut part = PartitionMut::new(&mut round[..], &sizes[..], &displs[..]);
                root.gather_varcount_into_root(&local[piece(r, local.len())], &mut part);
            }
            for (k, &c) in counts.iter().enumerate() {
                let p = piece(r, c);
                let (d, len) = (displs[k] as usize, p.len());
                buf[starts[k] + p.start..starts[k] + p.end].copy_from_slice(&round[d..d + len]);
            }
        }
        drop(local);
        Some(Gathered { bytes: buf, counts })
    }
    /// In pieces of at most [`chunk_bytes`] (32-bit counts).
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
        for piece in bytes.chunks_mut(chunk_bytes(1)) {
            root.broadcast_into(piece);
        }
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
