#pragma once
// Starting the program under test as a child process and waiting for it;
// a failed start or a crash fails the test.
#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>

#include <string>
#include <vector>

#include "cmocka_cpp.hpp"
#include "test_data.hpp"

extern char** environ;

namespace testing_support {

// Starts `program` (looked up on PATH when it has no slash) with `args`.
// With `out_path`, its stdout and stderr both go to that file.
inline pid_t spawn_program(const std::string& program, std::vector<std::string> args,
                           const std::string& out_path = "") {
  args.insert(args.begin(), program);
  std::vector<char*> argv;
  for (std::string& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  if (!out_path.empty()) {
    posix_spawn_file_actions_addopen(&actions, 1, out_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC,
                                     0644);
    posix_spawn_file_actions_adddup2(&actions, 1, 2);
  }
  pid_t pid = 0;
  assert_int_equal(posix_spawnp(&pid, program.c_str(), &actions, nullptr, argv.data(), environ), 0);
  posix_spawn_file_actions_destroy(&actions);
  return pid;
}

// Waits for the child and returns its exit status; a crash fails the test.
inline int wait_for_exit(pid_t pid) {
  int status = 0;
  assert_int_equal(waitpid(pid, &status, 0), pid);
  assert_true(WIFEXITED(status));  // never a crash
  return WEXITSTATUS(status);
}

inline int run_to_exit(const std::string& program, std::vector<std::string> args) {
  return wait_for_exit(spawn_program(program, std::move(args)));
}

// A run to its exit with what it printed (stdout and stderr together, by
// way of the file `out_path`).
struct RunOutput {
  int exit_status = -1;
  std::string out;
};

inline RunOutput run_capturing(const std::string& program, std::vector<std::string> args,
                               const std::string& out_path) {
  RunOutput r;
  r.exit_status = wait_for_exit(spawn_program(program, std::move(args), out_path));
  r.out = read_text(out_path);
  return r;
}

}  // namespace testing_support
