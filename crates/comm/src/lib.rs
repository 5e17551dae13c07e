//! The transport between the ranks that own subdomains and the root that
//! solves the interface problem (docs/architecture.md). The pipeline is written once
//! against [`Transport`]; [`Local`] runs every subdomain in one process (no
//! system packages needed), `Mpi` (cargo feature `mpi`, rsmpi) runs one rank
//! per process under `mpirun`. Nothing else in the workspace knows MPI exists.
//!
//! Messages are serde values encoded with bincode; collectives move one buffer
//! per rank (gather with variable counts, not one message per entry).
//!
//! The comm crate owns the transport; it must not know meshes, numerics or the
//! scene.

use serde::de::DeserializeOwned;
use serde::Serialize;

#[cfg(feature = "mpi")]
pub mod mpi_transport;
#[cfg(feature = "mpi")]
pub use mpi_transport::Mpi;

/// The collectives the pipeline needs. Rank 0 is the root.
pub trait Transport {
    fn rank(&self) -> usize;
    fn size(&self) -> usize;
    fn is_root(&self) -> bool {
        self.rank() == 0
    }
    /// Every rank's buffer, on the root (in rank order, in one allocation);
    /// `None` elsewhere.
    fn gather_bytes(&self, local: Vec<u8>) -> Option<Gathered>;
    /// The root's buffer, on every rank (`data` is read on the root only).
    fn broadcast_bytes(&self, data: Option<&[u8]>) -> Vec<u8>;
    /// Ends every rank at once with `code` (used on panics: never a hang).
    fn abort(&self, code: i32) -> !;
    /// Bytes this rank has sent so far.
    fn bytes_sent(&self) -> u64;
    /// A name for the report ("local" or "mpi").
    fn kind(&self) -> &'static str;
}

/// The buffers of every rank, end to end in one allocation (the root keeps
/// one copy of what the ranks sent, not two).
#[derive(Debug, Default)]
pub struct Gathered {
    pub bytes: Vec<u8>,
    /// Length of each rank's buffer, in rank order.
    pub counts: Vec<usize>,
}

impl Gathered {
    /// Each rank's buffer, in rank order.
    pub fn parts(&self) -> impl Iterator<Item = &[u8]> {
        self.counts.iter().scan(0, |start, &c| {
            let part = &self.bytes[*start..*start + c];
            *start += c;
            Some(part)
        })
    }
}

pub fn encode<T: Serialize>(v: &T) -> Vec<u8> {
    bincode::serde::encode_to_vec(v, bincode::config::standard())
        .expect("serialising plain data cannot fail")
}

pub fn decode<T: DeserializeOwned>(b: &[u8]) -> Result<T, String> {
    bincode::serde::decode_from_slice(b, bincode::config::standard())
        .map(|(v, _)| v)
        .map_err(|e| format!("corrupt message: {e}"))
}

/// Gathers a serde value from every rank on the root. With one rank the
/// root's value is the answer as it is: nothing is encoded or copied (the
/// condensed data of a body in many subdomains are gigabytes).
pub fn gather<T: Serialize + DeserializeOwned>(
    t: &dyn Transport,
    local: T,
) -> Result<Option<Vec<T>>, String> {
    if t.size() == 1 {
        return Ok(Some(vec![local]));
    }
    match t.gather_bytes(encode(&local)) {
        None => Ok(None),
        Some(all) => all
            .parts()
            .map(decode)
            .collect::<Result<Vec<_>, _>>()
            .map(Some),
    }
}

/// Broadcasts a serde value from the root (`value` is read on the root only).
pub fn broadcast<T: Serialize + DeserializeOwned>(
    t: &dyn Transport,
    value: Option<&T>,
) -> Result<T, String> {
    let bytes = value.map(encode);
    decode(&t.broadcast_bytes(bytes.as_deref()))
}

/// Every subdomain in this one process: one rank, no communication.
#[derive(Debug, Default)]
pub struct Local;

impl Transport for Local {
    fn rank(&self) -> usize {
        0
    }
    fn size(&self) -> usize {
        1
    }
    fn gather_bytes(&self, local: Vec<u8>) -> Option<Gathered> {
        Some(Gathered {
            counts: vec![local.len()],
            bytes: local,
        })
    }
    fn broadcast_bytes(&self, data: Option<&[u8]>) -> Vec<u8> {
        data.map(|d| d.to_vec()).unwrap_or_default()
    }
    fn abort(&self, code: i32) -> ! {
        std::process::exit(code)
    }
    fn bytes_sent(&self) -> u64 {
        0
    }
    fn kind(&self) -> &'static str {
        "local"
    }
}

/// The threads of one rank's dense and sparse kernels: `RAYON_NUM_THREADS`
/// when the user set it to a positive count (`user`), else the rank's share
/// of the cores it sees, max(1, cores / ranks_on_node), so that ranks
/// sharing a machine do not oversubscribe its cores (a rank bound to one
/// core by the launcher sees one core and gets one thread).
pub fn threads_per_rank(cores: usize, ranks_on_node: usize, user: Option<&str>) -> usize {
    if let Some(n) = user.and_then(|u| u.trim().parse::<usize>().ok()) {
        if n > 0 {
            return n;
        }
    }
    (cores / ranks_on_node.max(1)).max(1)
}

/// Deals subdomains with estimated costs to `ranks` ranks: each subdomain, in
/// decreasing cost, goes to the least loaded rank (ties: lowest rank). With as
/// many ranks as subdomains, subdomain k goes to rank k.
pub fn deal(costs: &[f64], ranks: usize) -> Vec<usize> {
    let ranks = ranks.max(1);
    if costs.len() == ranks {
        return (0..ranks).collect();
    }
    let mut order: Vec<usize> = (0..costs.len()).collect();
    order.sort_by(|&a, &b| costs[b].total_cmp(&costs[a]).then(a.cmp(&b)));
    let mut load = vec![0.0f64; ranks];
    let mut owner = vec![0; costs.len()];
    for s in order {
        let r = (0..ranks)
            .min_by(|&a, &b| load[a].total_cmp(&load[b]).then(a.cmp(&b)))
            .unwrap_or(0);
        owner[s] = r;
        load[r] += costs[s];
    }
    owner
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn local_gather_and_broadcast_round_trip_values() {
        let t = Local;
        let g = gather(&t, vec![1.5f64, -2.0]).unwrap().unwrap();
        assert_eq!(g, vec![vec![1.5, -2.0]]);
        let b: (String, u32) = broadcast(&t, Some(&("x".to_string(), 7))).unwrap();
        assert_eq!(b, ("x".to_string(), 7));
    }

    #[test]
    fn a_rank_gets_its_share_of_the_cores_unless_the_user_chose() {
        assert_eq!(threads_per_rank(8, 2, None), 4);
        assert_eq!(threads_per_rank(2, 2, None), 1);
        assert_eq!(threads_per_rank(2, 4, None), 1);
        assert_eq!(threads_per_rank(1, 1, None), 1);
        assert_eq!(threads_per_rank(8, 2, Some("3")), 3);
        assert_eq!(threads_per_rank(8, 2, Some("0")), 4);
        assert_eq!(threads_per_rank(8, 2, Some("many")), 4);
    }

    #[test]
    fn dealing_balances_costs_and_keeps_one_subdomain_per_rank_when_counts_match() {
        assert_eq!(deal(&[5.0, 1.0, 1.0], 3), vec![0, 1, 2]);
        let owner = deal(&[4.0, 3.0, 2.0, 2.0, 1.0], 2);
        let mut load = [0.0; 2];
        for (s, &r) in owner.iter().enumerate() {
            load[r] += [4.0, 3.0, 2.0, 2.0, 1.0][s];
        }
        assert_eq!(load, [6.0, 6.0]);
        assert_eq!(deal(&[1.0, 1.0], 1), vec![0, 0]);
    }
}
