#pragma once
// Which process runs a job: the `.claim` file in the job's directory, created exclusively (O_EXCL, atomic on
// a local disk and on NFS) and holding "HOST PID". The holder refreshes its modification time every few
// seconds while the run goes on (a heartbeat). A claim is stale when its process is gone (same host), or when
// it has not been refreshed for kClaimLeaseS (any host: a node lost, a worker killed with its whole process
// group). A stale claim is taken over by renaming it aside (one taker wins) and claiming anew, so a run whose
// worker died is run again, exactly once. Hosts sharing a directory need clocks that agree to well within
// the lease (NTP), as a lease is judged by the file's time against the local clock.

#include <string>

namespace sb::cli {

// Seconds without a heartbeat after which any host takes a claim over.
inline constexpr double kClaimLeaseS = 60.0;
// Seconds between heartbeats of a held claim.
inline constexpr double kClaimHeartbeatS = 2.0;

// Claims the job directory `dir` (which must exist) for this process; false when a live process holds it.
bool claimJob(const std::string& dir);
// Heartbeat: marks this process's claim of `dir` as alive.
void refreshClaim(const std::string& dir);
// Lets go of this process's claim of `dir` (a claim someone else took over is left alone).
void releaseClaim(const std::string& dir);
// "HOST PID" of this process, as its claims hold it.
std::string claimOwner();

}  // namespace sb::cli
