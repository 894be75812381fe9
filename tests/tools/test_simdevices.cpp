// simdevices, the built program, with commands written to its stdin the way
// a script writes them: several in one write(). Every one must be answered
// (it used to poll() the descriptor and read with stdio's buffered fgets,
// so the second of two commands written at once sat unread). A last
// command without its newline before end of input counts too.
//   argv[1]: the simdevices program
#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <string>

#include "cmocka_cpp.hpp"

extern char** environ;

namespace {

std::string g_program;
// The child of the running test: a failed assertion leaves the test by
// longjmp, past destructors, so the teardown ends it.
pid_t g_child = -1;

int end_child(void**) {
  if (g_child > 0) {
    kill(g_child, SIGTERM);
    waitpid(g_child, nullptr, 0);
  }
  g_child = -1;
  return 0;
}

// simdevices with pipes on its stdin and stdout.
struct Child {
  pid_t pid = -1;
  int in = -1, out = -1;  // our ends
  std::string seen;       // everything it printed so far

  Child() {
    int to_child[2], from_child[2];
    assert_int_equal(pipe(to_child), 0);
    assert_int_equal(pipe(from_child), 0);
    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    posix_spawn_file_actions_adddup2(&actions, to_child[0], 0);
    posix_spawn_file_actions_adddup2(&actions, from_child[1], 1);
    posix_spawn_file_actions_addclose(&actions, to_child[1]);
    posix_spawn_file_actions_addclose(&actions, from_child[0]);
    std::string program = g_program;
    char* argv[] = {program.data(), nullptr};
    assert_int_equal(posix_spawn(&pid, program.c_str(), &actions, nullptr, argv, environ), 0);
    posix_spawn_file_actions_destroy(&actions);
    g_child = pid;
    close(to_child[0]);
    close(from_child[1]);
    in = to_child[1];
    out = from_child[0];
  }
  ~Child() {
    if (in >= 0) close(in);
    if (out >= 0) close(out);
    if (pid > 0) {
      kill(pid, SIGTERM);
      waitpid(pid, nullptr, 0);
    }
    g_child = -1;
  }
  void send(const std::string& text) {
    // One write(): both commands reach the program together.
    assert_int_equal(write(in, text.data(), text.size()), static_cast<ssize_t>(text.size()));
  }
  // Reads its output until `text` has appeared `times` times, or the time
  // is up; returns whether it did.
  bool wait_for(const std::string& text, int times, int timeout_ms) {
    const auto end = std::chrono::steady_clock::now() + std::chrono::milliseconds(timeout_ms);
    for (;;) {
      int found = 0;
      for (std::size_t at = seen.find(text); at != std::string::npos;
           at = seen.find(text, at + 1)) {
        ++found;
      }
      if (found >= times) return true;
      const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(
                            end - std::chrono::steady_clock::now())
                            .count();
      if (left <= 0) return false;
      struct pollfd p = {out, POLLIN, 0};
      if (poll(&p, 1, static_cast<int>(left)) <= 0) continue;
      char buf[512];
      const ssize_t n = read(out, buf, sizeof(buf));
      if (n <= 0) return false;
      seen.append(buf, static_cast<std::size_t>(n));
    }
  }
  int wait_exit() {
    int status = 0;
    assert_int_equal(waitpid(pid, &status, 0), pid);
    pid = g_child = -1;
    assert_true(WIFEXITED(status));
    return WEXITSTATUS(status);
  }
};

void test_two_commands_in_one_write_are_both_answered(void**) {
  Child c;
  assert_true(c.wait_for("gripper board (115200 baud): ", 1, 10000));
  c.send("servo overheat 1 on\nstatus\n");
  // "ok" for the first, the status lines for the second, with the fault
  // the first switched on already in them (overheating: 0x04).
  const bool both = c.wait_for("servo 2: ", 1, 10000);
  if (!both) print_error("output so far:\n%s\n", c.seen.c_str());
  assert_true(both);
  assert_true(c.seen.find("ok\n") != std::string::npos);
  assert_true(c.seen.find("servo 1: ") != std::string::npos);
  assert_true(c.seen.find("error 0x04") != std::string::npos);
  assert_true(c.seen.find("gripper: encoder") != std::string::npos);
  // Three at once, a bad one among them: each answered, in order ("ok"
  // so far: the fault's and the status's).
  c.send("servo late 1000\nbogus\nservo late 0\n");
  assert_true(c.wait_for("ok\n", 4, 10000));
  const std::size_t bad = c.seen.find("? not understood");
  assert_true(bad != std::string::npos);
  assert_true(c.seen.rfind("ok\n") > bad);
  c.send("quit\n");
  assert_int_equal(c.wait_exit(), 0);
}

void test_a_command_split_across_writes_is_one_command(void**) {
  Child c;
  assert_true(c.wait_for("gripper board (115200 baud): ", 1, 10000));
  c.send("sta");
  c.send("tus\nservo noreply on\n");
  assert_true(c.wait_for("servo 2: ", 1, 10000));
  assert_true(c.wait_for("ok\n", 2, 10000));
  assert_true(c.seen.find("? not understood") == std::string::npos);
  // The last command without its newline, then end of input: answered.
  c.send("status");
  close(c.in);
  c.in = -1;
  assert_true(c.wait_for("servo 2: ", 2, 10000));
  // With its input closed it runs on (a background service) until a signal.
  kill(c.pid, SIGTERM);
  assert_int_equal(c.wait_exit(), 0);
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: %s SIMDEVICES\n", argv[0]);
    return 2;
  }
  g_program = argv[1];
  const struct CMUnitTest tests[] = {
      cmocka_unit_test_teardown(test_two_commands_in_one_write_are_both_answered, end_child),
      cmocka_unit_test_teardown(test_a_command_split_across_writes_is_one_command, end_child),
  };
  return cmocka_run_group_tests(tests, nullptr, nullptr);
}
