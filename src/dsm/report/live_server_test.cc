// SPDX-License-Identifier: MIT
#include "dsm/report/live_server.h"

#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <gtest/gtest.h>

#include "dsm/util/check.h"

namespace dsm {
namespace {

// One HTTP/1.0 request to 127.0.0.1:port; the whole response.
std::string Get(int port, const std::string& path) {
  const int fd = socket(AF_INET, SOCK_STREAM, 0);
  sockaddr_in address{};
  address.sin_family = AF_INET;
  address.sin_port = htons(static_cast<uint16_t>(port));
  address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  if (connect(fd, reinterpret_cast<sockaddr*>(&address), sizeof(address)) != 0) {
    close(fd);
    return "";
  }
  const std::string request = "GET " + path + " HTTP/1.0\r\nHost: localhost\r\n\r\n";
  EXPECT_EQ(send(fd, request.data(), request.size(), 0), static_cast<ssize_t>(request.size()));
  std::string response;
  char buffer[4096];
  for (ssize_t n; (n = recv(fd, buffer, sizeof(buffer), 0)) > 0;) response.append(buffer, n);
  close(fd);
  return response;
}

TEST(LiveServer, ServesThePageOnAFreePort) {
  LiveServer server(0, "<html>the page</html>");
  ASSERT_GT(server.port(), 0);
  const std::string page = Get(server.port(), "/");
  EXPECT_NE(page.find("200 OK"), std::string::npos) << page;
  EXPECT_NE(page.find("text/html"), std::string::npos) << page;
  EXPECT_NE(page.find("<html>the page</html>"), std::string::npos) << page;
  EXPECT_NE(Get(server.port(), "/other").find("404"), std::string::npos);
  server.Publish("{\"n\": 1}");  // No browser: nothing to send, nothing waits.
  EXPECT_EQ(server.NumConnections(), 0);
}

TEST(LiveServer, APortInUseIsAClearError) {
  LiveServer first(0, "x");
  try {
    LiveServer second(first.port(), "y");
    FAIL() << "second server on the same port";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("--port " + std::to_string(first.port())), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace dsm
