#include "server/HttpServer.h"

#include <poll.h>
#include <sys/socket.h>

#include <algorithm>
#include <cerrno>
#include <cstring>

namespace service::server {

namespace {

using Clock = std::chrono::steady_clock;

// Runs httplib's per-connection task at once, on its accept thread: the task only hands the
// socket to the Reception (process_and_close_socket below).
class InlineQueue final : public httplib::TaskQueue {
 public:
  void enqueue(std::function<void()> fn) override { fn(); }
  void shutdown() override {}
};

// Waits until fd is ready for `events`, at most until `deadline`.
bool waitFor(int fd, short events, Clock::time_point deadline) {
  for (;;) {
    const auto left =
        std::chrono::duration_cast<std::chrono::milliseconds>(deadline - Clock::now()).count();
    if (left <= 0) return false;
    pollfd p{fd, events, 0};
    const int r = ::poll(&p, 1, int(std::min<long long>(left, 1000000)));
    if (r > 0) return (p.revents & (events | POLLHUP | POLLERR)) != 0;
    if (r == 0) return false;
    if (errno != EINTR) return false;
  }
}

// httplib's Stream over a Connection: reads take what the Reception read first, then the
// socket, until the request's deadline; writes wait at most the write timeout each.
class ConnectionStream final : public httplib::Stream {
 public:
  ConnectionStream(Connection& c, Clock::time_point readDeadline,
                   std::chrono::milliseconds writeTimeout)
      : c_(c), readDeadline_(readDeadline), writeTimeout_(writeTimeout) {}

  bool is_readable() const override {
    return c_.pos < c_.buffer.size() || waitFor(c_.fd, POLLIN, readDeadline_);
  }
  bool is_writable() const override {
    if (!waitFor(c_.fd, POLLOUT, Clock::now() + writeTimeout_)) return false;
    // Alive: no end of stream waiting to be read (as httplib's is_socket_alive).
    char byte;
    const ssize_t n = ::recv(c_.fd, &byte, 1, MSG_PEEK | MSG_DONTWAIT);
    return n > 0 || (n < 0 && (errno == EAGAIN || errno == EWOULDBLOCK));
  }
  ssize_t read(char* ptr, size_t size) override {
    if (c_.pos >= c_.buffer.size()) {
      c_.buffer.clear();
      c_.pos = 0;
      if (!waitFor(c_.fd, POLLIN, readDeadline_)) return -1;
      char bytes[4096];
      ssize_t n;
      do n = ::recv(c_.fd, bytes, sizeof bytes, 0);
      while (n < 0 && errno == EINTR);
      if (n <= 0) return n;
      c_.buffer.assign(bytes, std::size_t(n));
    }
    const std::size_t n = std::min(size, c_.buffer.size() - c_.pos);
    std::memcpy(ptr, c_.buffer.data() + c_.pos, n);
    c_.pos += n;
    return ssize_t(n);
  }
  ssize_t write(const char* ptr, size_t size) override {
    if (!waitFor(c_.fd, POLLOUT, Clock::now() + writeTimeout_)) return -1;
    ssize_t n;
    do n = ::send(c_.fd, ptr, size, MSG_NOSIGNAL);
    while (n < 0 && errno == EINTR);
    return n;
  }
  void get_remote_ip_and_port(std::string& ip, int& port) const override {
    ip = c_.address;
    port = c_.port;
  }
  void get_local_ip_and_port(std::string& ip, int& port) const override {
    socketAddress(c_.fd, false, ip, port);
  }
  socket_t socket() const override { return c_.fd; }

 private:
  Connection& c_;
  Clock::time_point readDeadline_;
  std::chrono::milliseconds writeTimeout_;
};

}  // namespace

HttpServer::HttpServer(ReceptionOptions options, Reception::OnRefused onRefused)
    : options_(options) {
  new_task_queue = [] { return new InlineQueue(); };
  reception_ = std::make_unique<Reception>(
      options_, [this](Connection& c) { return serveRequest(c); }, std::move(onRefused));
}

HttpServer::~HttpServer() {
  reception_->stop();
}

int HttpServer::bind(const std::string& host, int port) {
  const int bound = port == 0 ? bind_to_any_port(host) : (bind_to_port(host, port) ? port : -1);
  if (bound <= 0) return -1;
  // The kernel caps the backlog at net.core.somaxconn.
  const int backlog = int(std::min<std::size_t>(options_.maxConnections, 65535));
  if (::listen(svr_sock_, std::max(backlog, 128)) != 0) return -1;
  return bound;
}

bool HttpServer::serve() {
  const bool ok = listen_after_bind();
  reception_->stop();
  return ok;
}

bool HttpServer::process_and_close_socket(socket_t sock) {
  reception_->admit(sock);
  return true;
}

bool HttpServer::serveRequest(Connection& c) {
  // The body, when there is one, gets the same time again from the end of the head.
  ConnectionStream stream(
      c, Clock::now() + options_.requestTimeout,
      std::chrono::milliseconds(write_timeout_sec_ * 1000 + write_timeout_usec_ / 1000));
  const bool last = c.requests + 1 >= keep_alive_max_count_ || svr_sock_ == INVALID_SOCKET;
  bool closed = false;
  const bool ok = process_request(stream, last, closed, nullptr);
  return ok && !closed && !last;
}

}  // namespace service::server
