#include "server/Reception.h"

#include <arpa/inet.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/eventfd.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>

#include <nlohmann/json.hpp>

namespace service::server {

namespace {

using Clock = std::chrono::steady_clock;

// GET /healthz and GET /metrics (with or without a query): served by the reserve.
bool isProbe(const std::string& buffer, std::size_t pos) {
  for (const char* probe : {"GET /healthz", "GET /metrics"}) {
    const std::size_t n = std::strlen(probe);
    if (buffer.compare(pos, n, probe) != 0) continue;
    const char next = pos + n < buffer.size() ? buffer[pos + n] : '\0';
    if (next == ' ' || next == '?') return true;
  }
  return false;
}

const char* reasonPhrase(int status) {
  switch (status) {
    case 408:
      return "Request Timeout";
    case 431:
      return "Request Header Fields Too Large";
    default:
      return "Service Unavailable";
  }
}

}  // namespace

void socketAddress(int fd, bool peer, std::string& ip, int& port) {
  sockaddr_storage addr{};
  socklen_t len = sizeof addr;
  ip = "?";
  port = 0;
  auto* a = reinterpret_cast<sockaddr*>(&addr);
  if ((peer ? getpeername(fd, a, &len) : getsockname(fd, a, &len)) != 0) return;
  char text[INET6_ADDRSTRLEN] = {};
  if (addr.ss_family == AF_INET) {
    const auto* in = reinterpret_cast<const sockaddr_in*>(&addr);
    inet_ntop(AF_INET, &in->sin_addr, text, sizeof text);
    port = ntohs(in->sin_port);
  } else if (addr.ss_family == AF_INET6) {
    const auto* in = reinterpret_cast<const sockaddr_in6*>(&addr);
    inet_ntop(AF_INET6, &in->sin6_addr, text, sizeof text);
    port = ntohs(in->sin6_port);
  }
  ip = text;
}

Reception::Reception(ReceptionOptions options, Serve serve, OnRefused onRefused)
    : options_(options), serve_(std::move(serve)), onRefused_(std::move(onRefused)) {
  wakeFd_ = eventfd(0, EFD_NONBLOCK | EFD_CLOEXEC);
  pool_ = std::make_unique<httplib::ThreadPool>(std::max<std::size_t>(1, options_.threads));
  reserve_ =
      std::make_unique<httplib::ThreadPool>(std::max<std::size_t>(1, options_.reserveThreads));
  thread_ = std::thread([this] { loop(); });
}

Reception::~Reception() {
  stop();
  if (wakeFd_ >= 0) ::close(wakeFd_);
}

void Reception::wake() {
  const std::uint64_t one = 1;
  [[maybe_unused]] const auto n = ::write(wakeFd_, &one, sizeof one);
}

void Reception::admit(int fd) {
  auto c = std::make_shared<Connection>();
  c->fd = fd;
  socketAddress(fd, true, c->address, c->port);
  c->deadline = Clock::now() + options_.requestTimeout;
  {
    std::lock_guard lock(mutex_);
    if (stopping_ || open_ >= options_.maxConnections) {
      // Past the process's share of sockets: no room even to read the request.
      ::shutdown(fd, SHUT_RDWR);
      ::close(fd);
      if (onRefused_) onRefused_("connections");
      return;
    }
    ++open_;
    const std::size_t n = ++perAddress_[c->address];
    c->overLimit = options_.maxPerAddress > 0 && n > options_.maxPerAddress;
    incoming_.push_back(c);
  }
  wake();
}

std::size_t Reception::openConnections() const {
  std::lock_guard lock(mutex_);
  return open_;
}

void Reception::close(const ConnectionPtr& c) {
  if (c->fd < 0) return;
  ::shutdown(c->fd, SHUT_RDWR);
  ::close(c->fd);
  c->fd = -1;
  std::lock_guard lock(mutex_);
  --open_;
  auto it = perAddress_.find(c->address);
  if (it != perAddress_.end() && --it->second == 0) perAddress_.erase(it);
}

void Reception::answerAndDrain(const ConnectionPtr& c, int status, const char* code,
                               const std::string& message) {
  const std::string body =
      nlohmann::json{{"error", {{"code", code}, {"message", message}}}}.dump() + "\n";
  std::string head =
      "HTTP/1.1 " + std::to_string(status) + " " + reasonPhrase(status) +
      "\r\nContent-Type: application/json\r\nContent-Length: " + std::to_string(body.size()) +
      "\r\nConnection: close\r\n";
  if (status == 503) head += "Retry-After: 1\r\n";
  const std::string answer = head + "\r\n" + body;
  // A few hundred bytes: they fit in the socket's send buffer, so this does not block.
  [[maybe_unused]] const auto n =
      ::send(c->fd, answer.data(), answer.size(), MSG_DONTWAIT | MSG_NOSIGNAL);
  ::shutdown(c->fd, SHUT_WR);
  c->draining = true;
  c->buffer.clear();
  c->pos = 0;
  c->deadline = Clock::now() + std::chrono::seconds(2);
  if (onRefused_)
    onRefused_(status == 408   ? "request_timeout"
               : status == 431 ? "head_too_large"
                               : "connections");
}

void Reception::readFrom(const ConnectionPtr& c, Clock::time_point now) {
  char bytes[4096];
  const ssize_t n = ::recv(c->fd, bytes, sizeof bytes, MSG_DONTWAIT);
  if (n == 0 || (n < 0 && errno != EAGAIN && errno != EWOULDBLOCK && errno != EINTR)) {
    close(c);  // the client closed, or the connection broke
    return;
  }
  if (n < 0 || c->draining) return;
  c->buffer.append(bytes, std::size_t(n));
  if (!c->started) {
    c->started = true;
    // A kept-alive connection's next request gets the whole timeout from its first byte.
    if (c->requests > 0) c->deadline = now + options_.requestTimeout;
  }
}

bool Reception::dispatch(const ConnectionPtr& c) {
  const bool probe = isProbe(c->buffer, c->pos);
  if (!probe && c->overLimit) {
    answerAndDrain(c, 503, "too_many_connections",
                   "at most " + std::to_string(options_.maxPerAddress) +
                       " connections from one address; close some and try again");
    return false;
  }
  c->started = false;
  (probe ? reserve_ : pool_)->enqueue([this, c] { serveOn(c); });
  return true;
}

void Reception::serveOn(const ConnectionPtr& c) {
  const bool keep = serve_(*c);
  ++c->requests;
  // What the request left unread stays for the next one (a pipelining client).
  c->buffer.erase(0, c->pos);
  c->pos = 0;
  if (keep && !stopped_.load()) {
    giveBack(c);
  } else {
    close(c);
  }
}

void Reception::giveBack(const ConnectionPtr& c) {
  c->deadline = Clock::now() + options_.keepAliveTimeout;
  {
    std::lock_guard lock(mutex_);
    if (!stopping_) {
      incoming_.push_back(c);
      wake();
      return;
    }
  }
  close(c);
}

void Reception::loop() {
  std::vector<ConnectionPtr> waiting;
  std::vector<pollfd> fds;
  for (;;) {
    {
      std::lock_guard lock(mutex_);
      if (stopping_) break;
      for (auto& c : incoming_) waiting.push_back(std::move(c));
      incoming_.clear();
    }
    auto now = Clock::now();
    // Heads that arrived whole (a pipelined request, given back with its head already read).
    for (auto& c : waiting) {
      if (c->fd < 0 || c->draining) continue;
      if (c->buffer.find("\r\n\r\n", c->pos) != std::string::npos && dispatch(c))
        c = nullptr;  // a thread has it now
    }
    std::erase_if(waiting, [](const ConnectionPtr& c) { return !c || c->fd < 0; });
    // Deadlines: a head that did not arrive in time is answered 408; an idle connection (no
    // byte of a next request) is closed quietly; a drained one is closed.
    for (auto& c : waiting) {
      if (c->deadline > now) continue;
      if (c->started && !c->draining) {
        answerAndDrain(c, 408, "request_timeout",
                       "the request did not arrive within " +
                           std::to_string(options_.requestTimeout.count() / 1000) + " s");
      } else {
        close(c);
      }
    }
    std::erase_if(waiting, [](const ConnectionPtr& c) { return c->fd < 0; });

    fds.assign(1, pollfd{wakeFd_, POLLIN, 0});
    auto next = now + std::chrono::seconds(1);
    for (const auto& c : waiting) {
      fds.push_back(pollfd{c->fd, POLLIN, 0});
      next = std::min(next, c->deadline);
    }
    const auto wait = std::chrono::duration_cast<std::chrono::milliseconds>(next - now).count();
    const int ready = ::poll(fds.data(), fds.size(), int(std::clamp<long long>(wait, 0, 1000)) + 1);
    if (ready < 0 && errno != EINTR) break;
    if (fds[0].revents & POLLIN) {
      std::uint64_t count = 0;
      [[maybe_unused]] const auto n = ::read(wakeFd_, &count, sizeof count);
    }
    now = Clock::now();
    for (std::size_t i = 1; i < fds.size(); ++i) {
      if (!fds[i].revents) continue;
      const ConnectionPtr& c = waiting[i - 1];
      readFrom(c, now);
      if (c->fd < 0 || c->draining) continue;
      if (c->buffer.find("\r\n\r\n", c->pos) != std::string::npos) {
        if (dispatch(c)) waiting[i - 1] = nullptr;
      } else if (c->buffer.size() - c->pos > kMaxHead) {
        answerAndDrain(
            c, 431, "head_too_large",
            "the request line and headers are longer than " + std::to_string(kMaxHead) + " bytes");
      }
    }
    std::erase_if(waiting, [](const ConnectionPtr& c) { return !c || c->fd < 0; });
  }
  for (auto& c : waiting) close(c);
}

void Reception::stop() {
  if (stopped_.exchange(true)) return;
  {
    std::lock_guard lock(mutex_);
    stopping_ = true;
  }
  wake();
  if (thread_.joinable()) thread_.join();
  std::vector<ConnectionPtr> left;
  {
    std::lock_guard lock(mutex_);
    left.swap(incoming_);
  }
  for (auto& c : left) close(c);
  // The requests being served end (their answers go out), then the threads.
  pool_->shutdown();
  reserve_->shutdown();
  left.clear();
  {
    std::lock_guard lock(mutex_);
    left.swap(incoming_);
  }
  for (auto& c : left) close(c);
}

}  // namespace service::server
