// posix_spawn-based child processes.
#include "tests/support/process.h"

#include "common/film/image_io.h"

#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstring>
#include <fstream>
#include <sstream>
#include <thread>

extern char** environ;

namespace pathfarm::test {

Process::Process(const std::vector<std::string>& argv, const std::string& log_path)
    : log_(log_path) {
    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    posix_spawn_file_actions_addopen(&actions, STDOUT_FILENO, log_path.c_str(),
                                     O_WRONLY | O_CREAT | O_TRUNC, 0644);
    posix_spawn_file_actions_adddup2(&actions, STDOUT_FILENO, STDERR_FILENO);
    std::vector<char*> args;
    for (const std::string& a : argv)
        args.push_back(const_cast<char*>(a.c_str()));
    args.push_back(nullptr);
    if (posix_spawn(&pid_, args[0], &actions, nullptr, args.data(), environ) != 0) pid_ = -1;
    posix_spawn_file_actions_destroy(&actions);
}

Process::~Process() {
    if (pid_ > 0 && !exit_) {
        ::kill(pid_, SIGKILL);
        wait(std::chrono::milliseconds(5000));
    }
}

std::optional<int> Process::wait(std::chrono::milliseconds timeout) {
    if (exit_ || pid_ <= 0) return exit_;
    const auto end = std::chrono::steady_clock::now() + timeout;
    do {
        int status = 0;
        if (waitpid(pid_, &status, WNOHANG) == pid_) {
            exit_ = WIFEXITED(status) ? WEXITSTATUS(status) : -WTERMSIG(status);
            return exit_;
        }
        std::this_thread::sleep_for(std::chrono::milliseconds(20));
    } while (std::chrono::steady_clock::now() < end);
    return std::nullopt;
}

void Process::kill(int signal) {
    if (pid_ > 0 && !exit_) ::kill(pid_, signal);
}

std::string read_file(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    std::stringstream s;
    s << in.rdbuf();
    return s.str();
}

std::optional<std::string> wait_for_text(const std::string& path, const std::string& needle,
                                         std::chrono::milliseconds timeout) {
    const auto end = std::chrono::steady_clock::now() + timeout;
    do {
        const std::string text = read_file(path);
        if (const auto at = text.find(needle); at != std::string::npos) {
            const auto from = at + needle.size();
            return text.substr(from, text.find('\n', from) - from);
        }
        std::this_thread::sleep_for(std::chrono::milliseconds(20));
    } while (std::chrono::steady_clock::now() < end);
    return std::nullopt;
}

bool images_identical(const std::string& a, const std::string& b) {
    auto x = read_image(a), y = read_image(b);
    return x.ok() && y.ok() && x->width == y->width && x->height == y->height &&
           x->rgb.size() == y->rgb.size() &&
           std::memcmp(x->rgb.data(), y->rgb.data(), x->rgb.size() * sizeof(float)) == 0;
}

bool files_identical(const std::string& a, const std::string& b) {
    const std::string x = read_file(a), y = read_file(b);
    return !x.empty() && x == y;
}

}  // namespace pathfarm::test
