// SPDX-License-Identifier: MIT
#include "dsm/report/live_server.h"

#include <chrono>
#include <future>
#include <mutex>
#include <set>
#include <thread>

#include <websocketpp/config/asio_no_tls.hpp>
#include <websocketpp/server.hpp>

#include "dsm/util/check.h"

namespace dsm {

using WsServer = websocketpp::server<websocketpp::config::asio>;
using Handle = websocketpp::connection_hdl;

struct LiveServer::Impl {
  WsServer server;
  std::string page;
  std::thread thread;
  mutable std::mutex mutex;
  std::shared_ptr<const std::string> latest;                  // Guarded by mutex.
  std::set<Handle, std::owner_less<Handle>> connections;      // The server thread's.
  int port = 0;

  // On the server thread.
  void Send(const Handle& h, const std::shared_ptr<const std::string>& document) {
    std::error_code ec;
    WsServer::connection_ptr con = server.get_con_from_hdl(h, ec);
    if (ec || !document || con->get_buffered_amount() > kMaxQueuedBytes) return;
    con->send(*document, websocketpp::frame::opcode::text);  // Errors: the close handler follows.
  }
};

LiveServer::LiveServer(int port, std::string page) : impl_(std::make_unique<Impl>()) {
  Impl& m = *impl_;
  m.page = std::move(page);
  m.server.clear_access_channels(websocketpp::log::alevel::all);
  m.server.clear_error_channels(websocketpp::log::elevel::all);
  m.server.init_asio();
  m.server.set_reuse_addr(true);
  m.server.set_http_handler([&m](Handle h) {
    WsServer::connection_ptr con = m.server.get_con_from_hdl(h);
    const std::string resource = con->get_resource();
    if (resource == "/" || resource.rfind("/?", 0) == 0 || resource == "/index.html") {
      con->set_status(websocketpp::http::status_code::ok);
      con->replace_header("Content-Type", "text/html; charset=utf-8");
      con->replace_header("Cache-Control", "no-store");
      con->set_body(m.page);
    } else {
      con->set_status(websocketpp::http::status_code::not_found);
      con->set_body("not found\n");
    }
  });
  m.server.set_validate_handler([&m](Handle h) { return m.server.get_con_from_hdl(h)->get_resource() == "/ws"; });
  m.server.set_open_handler([&m](Handle h) {
    m.connections.insert(h);
    std::shared_ptr<const std::string> latest;
    {
      std::lock_guard<std::mutex> lock(m.mutex);
      latest = m.latest;
    }
    m.Send(h, latest);
  });
  m.server.set_close_handler([&m](Handle h) { m.connections.erase(h); });
  m.server.set_fail_handler([&m](Handle h) { m.connections.erase(h); });
  std::error_code ec;
  m.server.listen(boost::asio::ip::tcp::endpoint(boost::asio::ip::address_v4::loopback(),
                                                 static_cast<unsigned short>(port)), ec);
  if (ec) throw InputError("--port " + std::to_string(port) + ": cannot listen on localhost (" + ec.message() + ")");
  boost::system::error_code endpoint_ec;
  m.port = m.server.get_local_endpoint(endpoint_ec).port();
  m.server.start_accept(ec);
  if (ec) throw InputError("--port " + std::to_string(port) + ": " + ec.message());
  m.thread = std::thread([&m] { m.server.run(); });
}

LiveServer::~LiveServer() {
  Impl& m = *impl_;
  boost::asio::post(m.server.get_io_service(), [&m] {
    std::error_code ec;
    m.server.stop_listening(ec);
    for (const Handle& h : m.connections) m.server.close(h, websocketpp::close::status::going_away, "run ended", ec);
  });
  // Closing handshakes get a moment; then the loop stops whatever is left.
  std::this_thread::sleep_for(std::chrono::milliseconds(100));
  m.server.stop();
  m.thread.join();
}

int LiveServer::port() const { return impl_->port; }

void LiveServer::Publish(std::string document) {
  Impl& m = *impl_;
  auto shared = std::make_shared<const std::string>(std::move(document));
  {
    std::lock_guard<std::mutex> lock(m.mutex);
    m.latest = shared;
  }
  boost::asio::post(m.server.get_io_service(), [&m, shared] {
    for (const Handle& h : m.connections) m.Send(h, shared);
  });
}

int LiveServer::NumConnections() const {
  // Read on the server thread would need a round trip; the count is for tests and messages only.
  std::promise<int> count;
  boost::asio::post(impl_->server.get_io_service(), [this, &count] { count.set_value(static_cast<int>(impl_->connections.size())); });
  return count.get_future().get();
}

}  // namespace dsm
