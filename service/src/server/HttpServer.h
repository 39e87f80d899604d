#pragma once
// cpp-httplib's server (the Debian 12 library, 0.11.4) with its connections handled by the
// Reception (server/Reception.h) instead of one pool thread each from accept to close:
// httplib's accept loop hands each socket over at once, the Reception waits for a request's
// whole head without a thread, and a thread then runs httplib's own request handling
// (Server::process_request) on a stream over the connection. Routing, handlers and responses
// are httplib's, unchanged.
//
// httplib 0.11.4 listens with a backlog of 5 (CPPHTTPLIB_LISTEN_BACKLOG, compiled into the
// library): a burst of 100 connections overflowed it and clients got TCP resets. bind() listens
// again with a backlog as large as the connections the server takes (Linux updates the backlog
// of a socket that listens already).
#include <memory>
#include <string>

#include <httplib.h>

#include "server/Reception.h"

namespace service::server {

class HttpServer : public httplib::Server {
 public:
  explicit HttpServer(ReceptionOptions options, Reception::OnRefused onRefused = {});
  ~HttpServer() override;

  // Binds host:port (port 0: any free port) and sets the backlog; the port, or -1.
  int bind(const std::string& host, int port);
  // Serves until stop() (httplib::Server::stop), then waits for the requests being served.
  bool serve();
  std::size_t openConnections() const { return reception_->openConnections(); }

 private:
  bool process_and_close_socket(socket_t sock) override;
  bool serveRequest(Connection& c);

  ReceptionOptions options_;
  std::unique_ptr<Reception> reception_;
};

}  // namespace service::server
