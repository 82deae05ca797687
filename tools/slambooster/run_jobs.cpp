#include "tools/slambooster/run_jobs.h"

#include <fcntl.h>
#include <sys/prctl.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <climits>
#include <deque>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <map>
#include <sstream>
#include <thread>
#include <type_traits>

#include "core/config_reader.h"
#include "core/error.h"
#include "core/input_file.h"
#include "drivers/tum_layout.h"
#include "tools/slambooster/claim.h"

namespace sb::cli {

namespace fs = std::filesystem;

std::string selfExecutable() {
  char buffer[PATH_MAX];
  const ssize_t n = readlink("/proc/self/exe", buffer, sizeof(buffer) - 1);
  if (n <= 0) throw Error("cannot find the slambooster executable (/proc/self/exe)");
  return std::string(buffer, static_cast<size_t>(n));
}

namespace {

pid_t spawn(const std::string& exe, const Job& job) {
  std::vector<std::string> args = {exe, "run"};
  args.insert(args.end(), job.runArgs.begin(), job.runArgs.end());
  if (job.argsAtStart) {
    const std::vector<std::string> more = job.argsAtStart();
    args.insert(args.end(), more.begin(), more.end());
  }
  // The experiment matrix reproduces the paper: a fixed volume (docs/moving-volume.md).
  args.insert(args.end(), {"--out", job.outDir, "--quiet", "--fixed-volume"});
  const std::string log = job.outDir + "/run.log";
  const pid_t parent = getpid();
  const pid_t pid = fork();
  if (pid < 0) throw Error("cannot start a process for job " + job.id);
  if (pid == 0) {
    // The run dies with its worker (killed, or its node's job cancelled): no orphan writes into a job
    // directory whose claim another worker takes over.
    prctl(PR_SET_PDEATHSIG, SIGKILL);
    if (getppid() != parent) _exit(127);
    const int fd = open(log.c_str(), O_CREAT | O_TRUNC | O_WRONLY, 0644);
    if (fd >= 0) {
      dup2(fd, STDOUT_FILENO);
      dup2(fd, STDERR_FILENO);
      close(fd);
    }
    std::vector<char*> argv;
    for (auto& a : args) argv.push_back(a.data());
    argv.push_back(nullptr);
    execv(exe.c_str(), argv.data());
    _exit(127);
  }
  return pid;
}

}  // namespace

bool jobDone(const std::string& outDir) {
  return runSummaryComplete(outDir + "/summary.json");  // missing or not JSON: not done
}

RunSummary readSummary(const std::string& outDir) {
  return readRunDirSummary(outDir, "did the run finish? (see run.log there)");
}

void runJobs(const std::vector<Job>& jobs, int parallel, bool quiet) {
  const std::string exe = selfExecutable();
  std::deque<const Job*> todo;
  for (const Job& j : jobs)
    if (!jobDone(j.outDir)) todo.push_back(&j);
  const size_t total = jobs.size(), alreadyDone = total - todo.size(), toRun = todo.size();
  if (!quiet)
    std::cerr << "jobs: " << total << " (" << alreadyDone << " already done, " << toRun << " to run, " << parallel
              << " at a time)\n";
  std::map<pid_t, const Job*> running;
  std::vector<const Job*> elsewhere;  // claimed by another live process: waited for, taken over if it dies
  std::vector<std::string> failures;
  size_t finished = 0;
  bool toldWaiting = false;
  const auto start = std::chrono::steady_clock::now();
  auto lastBeat = start;
  while (!todo.empty() || !running.empty() || !elsewhere.empty()) {
    while (!todo.empty() && static_cast<int>(running.size()) < parallel) {
      const Job& job = *todo.front();
      todo.pop_front();
      fs::create_directories(job.outDir);
      if (!claimJob(job.outDir)) {
        elsewhere.push_back(&job);
      } else if (jobDone(job.outDir)) {  // another process finished it and let go of it meanwhile
        releaseClaim(job.outDir);
      } else {
        running[spawn(exe, job)] = &job;
      }
    }
    if (running.empty()) {
      // Only other processes' runs are left: look again every second, and claim those whose process is gone.
      for (const Job* job : elsewhere)
        if (!jobDone(job->outDir)) todo.push_back(job);
      elsewhere.clear();
      if (todo.empty()) break;
      if (!quiet && !toldWaiting)
        std::cerr << "waiting for " << todo.size() << " runs that another process is running, e.g. "
                  << todo.front()->outDir << " (taken over if that process stops, or, on another host, if its "
                  << "claim goes " << kClaimLeaseS << " s without a heartbeat)\n";
      toldWaiting = true;
      std::this_thread::sleep_for(std::chrono::seconds(1));
      continue;
    }
    int status = 0;
    const pid_t pid = waitpid(-1, &status, WNOHANG);
    if (pid < 0) break;
    if (pid == 0) {  // all still running: keep their claims alive
      const auto now = std::chrono::steady_clock::now();
      if (std::chrono::duration<double>(now - lastBeat).count() >= kClaimHeartbeatS) {
        for (const auto& [child, job] : running) refreshClaim(job->outDir);
        lastBeat = now;
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(100));
      continue;
    }
    const auto it = running.find(pid);
    if (it == running.end()) continue;
    const Job& job = *it->second;
    running.erase(it);
    releaseClaim(job.outDir);
    ++finished;
    const bool ok = WIFEXITED(status) && WEXITSTATUS(status) == 0 && jobDone(job.outDir);
    if (!ok) failures.push_back(job.id + " (log: " + job.outDir + "/run.log)");
    if (!quiet) {
      const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      const double eta = elapsed / double(finished) * double(todo.size() + running.size());
      std::cerr << "[" << alreadyDone + finished << "/" << total << "] " << job.id << (ok ? " done" : " FAILED")
                << ", " << std::fixed << std::setprecision(0) << elapsed << " s elapsed, ~" << eta << " s left\n";
    }
  }
  if (!failures.empty()) {
    std::string list;
    for (const auto& f : failures) list += "\n  " + f;
    throw Error(std::to_string(failures.size()) + " of " + std::to_string(toRun) + " runs failed:" + list);
  }
}

std::vector<Knobs> knobGrid(const std::vector<int>& csr, const std::vector<double>& icp, const std::vector<int>& pd0,
                            const std::vector<int>& ir) {
  std::vector<Knobs> grid;
  for (int c : csr)
    for (double i : icp)
      for (int p : pd0)
        for (int r : ir) {
          Knobs k;
          k.csr = c;
          k.icpThreshold = i;
          k.pyramidIterations[0] = p;
          k.integrationRate = r;
          validateKnobs(k);
          grid.push_back(k);
        }
  return grid;
}

std::string knobsId(const Knobs& k) {
  std::ostringstream s;  // csr1_icp1e-05_pd10-5-4_tr1_ir2: each knob by its name, pd's levels joined by '-'
  forEachKnobField(k, [&s](const char* name, const auto& value) {
    s << (s.tellp() > 0 ? "_" : "") << name;
    if constexpr (std::is_arithmetic_v<std::decay_t<decltype(value)>>) {
      s << value;
    } else {
      for (size_t i = 0; i < value.size(); ++i) s << (i ? "-" : "") << value[i];
    }
  });
  return s.str();
}

std::string sequenceName(const std::string& path) {
  fs::path p(path);
  while (!p.empty() && p.filename().empty()) p = p.parent_path();
  if (p.filename() == tum::kIndexFile) p = p.parent_path();
  return p.stem().string();
}

}  // namespace sb::cli
