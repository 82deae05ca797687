// core/input_file.h (issue 33): nothing read blocks on a FIFO, socket or device; messages say what a path
// really is; control bytes are escaped and long values cut. A blocking open() would hang the test, so every
// FIFO case runs under a watchdog thread that fails it after a few seconds instead.

#include "core/input_file.h"

#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/un.h>
#include <unistd.h>

#include <catch2/catch.hpp>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <future>
#include <string>

#include "core/error.h"
#include "core/config_reader.h"
#include "core/json_text.h"
#include "core/png_io.h"
#include "core/trajectory.h"

namespace fs = std::filesystem;

namespace {

struct TempDir {
  std::string path;
  TempDir() {
    char t[] = "/tmp/sb-input-file-XXXXXX";
    path = ::mkdtemp(t);
  }
  ~TempDir() {
    std::error_code ec;
    fs::permissions(path + "/locked", fs::perms::owner_all, ec);
    fs::remove_all(path, ec);
  }
};

// The message of the sb::Error `fn` throws, or "" when it throws none; fails the test when it takes longer
// than 5 s (a blocking open of a FIFO) — the blocked thread is then left behind.
template <typename Fn>
std::string errorOf(Fn fn) {
  auto result = std::async(std::launch::async, [fn]() -> std::string {
    try {
      fn();
    } catch (const sb::Error& e) {
      return e.what();
    }
    return "";
  });
  if (result.wait_for(std::chrono::seconds(5)) != std::future_status::ready) {
    FAIL("blocked for 5 s (a FIFO opened in blocking mode?)");
    std::quick_exit(1);  // the blocked thread would keep the test from ending
  }
  return result.get();
}

}  // namespace

TEST_CASE("pathProblem names what a path really is", "[core][input_file]") {
  TempDir tmp;
  const std::string fifo = tmp.path + "/fifo", file = tmp.path + "/file", loop = tmp.path + "/loop";
  REQUIRE(::mkfifo(fifo.c_str(), 0600) == 0);
  std::ofstream(file) << "x";
  fs::create_symlink(loop, loop);
  fs::create_symlink(tmp.path + "/nothing", tmp.path + "/dangling");
  CHECK(sb::pathProblem(file).empty());
  CHECK(sb::pathProblem(tmp.path + "/nothing") == "does not exist");
  CHECK(sb::pathProblem(fifo).find("named pipe (FIFO)") != std::string::npos);
  CHECK(sb::pathProblem(tmp.path) == "is a directory");
  CHECK(sb::pathProblem("/dev/zero").find("character device") != std::string::npos);
  CHECK(sb::pathProblem(loop).find("symbolic-link loop") != std::string::npos);
  CHECK(sb::pathProblem(tmp.path + "/dangling").find("symbolic link to something that does not exist") !=
        std::string::npos);
  CHECK(sb::pathProblem(file + "/below").find("not a directory") != std::string::npos);
  // A Unix socket.
  const std::string sock = tmp.path + "/s";
  const int fd = ::socket(AF_UNIX, SOCK_STREAM, 0);
  sockaddr_un addr{};
  addr.sun_family = AF_UNIX;
  std::snprintf(addr.sun_path, sizeof addr.sun_path, "%s", sock.c_str());
  REQUIRE(::bind(fd, reinterpret_cast<sockaddr*>(&addr), sizeof addr) == 0);
  CHECK(sb::pathProblem(sock).find("socket") != std::string::npos);
  ::close(fd);
  if (::geteuid() != 0) {  // root reads everything: the permission case needs an ordinary user
    fs::create_directory(tmp.path + "/locked");
    std::ofstream(tmp.path + "/locked/f") << "x";
    fs::permissions(tmp.path + "/locked", fs::perms::none);
    CHECK(sb::pathProblem(tmp.path + "/locked/f").find("permission denied") != std::string::npos);
  }
}

TEST_CASE("no reader blocks on a FIFO: JSON, trajectories, PNGs, text streams", "[core][input_file]") {
  TempDir tmp;
  const std::string fifo = tmp.path + "/fifo";
  REQUIRE(::mkfifo(fifo.c_str(), 0600) == 0);
  const auto isFifoError = [](const std::string& message) {
    INFO(message);
    CHECK(message.find("named pipe (FIFO)") != std::string::npos);
    CHECK(message.find(" '") != std::string::npos);  // names the path
  };
  isFifoError(errorOf([&] { sb::readJsonConfig(fifo, "config file"); }));
  isFifoError(errorOf([&] { sb::readTumTrajectory(fifo); }));
  isFifoError(errorOf([&] { sb::readPng16(fifo); }));
  isFifoError(errorOf([&] { sb::InputFile in(fifo, "log"); }));
  // Devices are refused too, never opened.
  CHECK(errorOf([&] { sb::readJsonConfig("/dev/zero", "config file"); }).find("character device") !=
        std::string::npos);
  // A directory is not "missing" and has no poses: it is a directory.
  CHECK(errorOf([&] { sb::readTumTrajectory(tmp.path); }).find("is a directory") != std::string::npos);
}

TEST_CASE("InputFile reads a regular file like an ifstream", "[core][input_file]") {
  TempDir tmp;
  const std::string file = tmp.path + "/lines.txt";
  std::string expected;
  {
    std::ofstream out(file);
    for (int i = 0; i < 20000; ++i) {  // more than one 64 KiB buffer
      out << "line " << i << "\n";
      expected += "line " + std::to_string(i) + "\n";
    }
  }
  sb::InputFile in(file, "text");
  std::string read, line;
  while (std::getline(in, line)) read += line + "\n";
  CHECK(read == expected);
  CHECK(in.eof());
  CHECK_FALSE(in.bad());
}

TEST_CASE("printable escapes control bytes and cuts long values", "[core][input_file]") {
  CHECK(sb::printable("a\x1b[31mred\x07\n\tb") == "a\\x1b[31mred\\x07\n\tb");
  CHECK(sb::printable(std::string("nul\0byte", 8)) == "nul\\x00byte");
  const std::string huge(20u << 20, 'x');  // a 20 MB value
  const std::string cut = sb::printable(huge);
  CHECK(cut.size() < 4200);
  CHECK(cut.find("bytes cut") != std::string::npos);
  CHECK(sb::quoteForMessage("a\nb") == "'a\\x0ab'");
  CHECK(sb::quoteForMessage(huge).size() < 400);
}
