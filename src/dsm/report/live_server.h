// SPDX-License-Identifier: MIT
// The live viewer's server (dsm run --view): serves one HTML page at / and pushes JSON documents
// to every browser connected to the WebSocket /ws, on a thread of its own (websocketpp over
// Boost.Asio). Publishing never waits for a browser: a document is queued per connection only
// while that connection has less than kMaxQueuedBytes still unsent, otherwise that browser skips
// it and gets the next one.
#pragma once

#include <memory>
#include <string>

namespace dsm {

class LiveServer {
 public:
  static constexpr size_t kMaxQueuedBytes = 16 << 20;

  // Listens on 127.0.0.1:port (0: a free port); throws InputError when it cannot.
  LiveServer(int port, std::string page);
  ~LiveServer();  // Closes the connections and stops the thread.
  LiveServer(const LiveServer&) = delete;
  LiveServer& operator=(const LiveServer&) = delete;

  int port() const;
  // The newest document: sent to the connected browsers now and to each browser that connects.
  void Publish(std::string document);
  int NumConnections() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace dsm
