#pragma once
// The reception of the HTTP server: every accepted connection waits here, in one poll loop that
// costs no thread per connection, until the head of its next request (request line and headers)
// has arrived whole. Only then does a thread serve it. So a client that sends its head one byte
// a second holds a socket, not one of the threads that answer everyone else, and it is closed
// (408) when its head has not arrived within the request timeout: a deadline for the whole
// head, where a timeout per read would let it trickle on for ever.
//
// Open connections per client address are capped: past the cap a request is answered 503
// (too_many_connections) once its head is read. Health checks and metrics (GET /healthz,
// GET /metrics) are exempt from the cap and are served by threads of their own, so that they
// answer within milliseconds whatever the other requests do (event streams and renders hold the
// main threads for seconds).
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstddef>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include <httplib.h>

namespace service::server {

// One client connection between its requests, or while a thread serves one.
struct Connection {
  int fd = -1;
  std::string address;  // the peer's IP address, the key of the per-address cap
  int port = 0;
  std::string buffer;   // bytes read from the socket and not yet consumed
  std::size_t pos = 0;  // buffer[pos...] is unconsumed
  std::chrono::steady_clock::time_point deadline;
  bool started = false;    // the current request's first byte has arrived
  bool overLimit = false;  // admitted past its address's cap
  bool draining = false;   // answered and half-closed: reading what is left before closing
  std::size_t requests = 0;
};

// The IP address and port of a socket's peer (peer) or its own end, as text.
void socketAddress(int fd, bool peer, std::string& ip, int& port);

struct ReceptionOptions {
  std::chrono::milliseconds requestTimeout{10000};   // a request's head must arrive within it
  std::chrono::milliseconds keepAliveTimeout{5000};  // idle time between requests
  std::size_t maxPerAddress = 64;                    // open connections per address; 0: no cap
  std::size_t maxConnections = 1000;                 // open connections in all
  std::size_t threads = 32;                          // threads serving requests
  std::size_t reserveThreads = 2;                    // threads serving /healthz and /metrics
};

class Reception {
 public:
  // Serves one request of the connection on the calling thread; true when the connection stays
  // open for another request (keep-alive).
  using Serve = std::function<bool(Connection&)>;
  // Called for each connection refused, with the reason ("connections", "request_timeout",
  // "head_too_large"): the server counts them.
  using OnRefused = std::function<void(const char* reason)>;

  Reception(ReceptionOptions options, Serve serve, OnRefused onRefused);
  ~Reception();  // stop()
  Reception(const Reception&) = delete;
  Reception& operator=(const Reception&) = delete;

  // Takes an accepted socket (from any thread): it waits here for its first request's head.
  void admit(int fd);
  // Closes the waiting connections and waits for the requests being served to end.
  void stop();
  std::size_t openConnections() const;

  // A request head is whole once its blank line has arrived; heads longer than this are refused.
  static constexpr std::size_t kMaxHead = 16384;

 private:
  using ConnectionPtr = std::shared_ptr<Connection>;
  void loop();
  void readFrom(const ConnectionPtr& c, std::chrono::steady_clock::time_point now);
  // To a thread (true), or answered here (a connection past its address's cap).
  bool dispatch(const ConnectionPtr& c);
  void serveOn(const ConnectionPtr& c);
  void giveBack(const ConnectionPtr& c);
  // Writes a short answer, half-closes, and keeps reading until the client closes (a close with
  // unread bytes would reset the connection before the client reads the answer).
  void answerAndDrain(const ConnectionPtr& c, int status, const char* code,
                      const std::string& message);
  void close(const ConnectionPtr& c);
  void wake();

  ReceptionOptions options_;
  Serve serve_;
  OnRefused onRefused_;
  mutable std::mutex mutex_;
  std::vector<ConnectionPtr> incoming_;  // admitted or given back, not yet in the loop
  std::map<std::string, std::size_t> perAddress_;
  std::size_t open_ = 0;
  bool stopping_ = false;
  int wakeFd_ = -1;  // an eventfd: a new connection or stop() interrupts the poll
  std::thread thread_;
  std::unique_ptr<httplib::ThreadPool> pool_, reserve_;
  std::atomic<bool> stopped_{false};
};

}  // namespace service::server
