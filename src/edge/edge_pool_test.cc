// SPDX-License-Identifier: LGPL-2.1-only
// The load-balancing client's pieces without sockets: the reorder buffer (answers and losses
// out of order leave in input order, duplicates ignored) and the dest-host list grammar.
#include "edge/edge_pool.h"

#include <gtest/gtest.h>

#include "core/error.h"

using namespace nns::edge;

namespace {

Message msg(uint8_t v) {
  Message m;
  m.mems.push_back(heap_payload(1));
  m.mems[0]->data()[0] = v;
  return m;
}

}  // namespace

TEST(EdgePool, InOrderReleasesInInputOrder) {
  InOrder<int> q;
  for (int i = 0; i < 5; ++i) q.add(static_cast<uint64_t>(i), 100 + i);
  std::vector<int> got;
  auto pop = [&] {
    q.pop_ready([&](int &p, Message &&m) { got.push_back(p * 1000 + m.mems[0]->data()[0]); },
                [&](int &p) { got.push_back(-p); });
  };
  EXPECT_TRUE(q.answer(2, msg(2)));
  EXPECT_TRUE(q.lose(1));
  pop();
  EXPECT_TRUE(got.empty());           // 0 still missing
  EXPECT_FALSE(q.answer(2, msg(9)));  // a duplicate (re-sent and answered twice) is ignored
  EXPECT_TRUE(q.answer(0, msg(0)));
  pop();
  EXPECT_EQ(got, (std::vector<int>{100000, -101, 102002}));
  EXPECT_EQ(q.size(), 2u);
  EXPECT_FALSE(q.answer(0, msg(0)));  // already left
  EXPECT_FALSE(q.lose(7));            // never added
  EXPECT_TRUE(q.answer(4, msg(4)));
  EXPECT_TRUE(q.answer(3, msg(3)));
  pop();
  EXPECT_EQ(got.back(), 104004);
  EXPECT_EQ(q.size(), 0u);
}

TEST(EdgePool, EndpointList) {
  const auto e = parse_endpoints("10.0.0.5, 10.0.0.6:3002,host", 3000);
  ASSERT_EQ(e.size(), 3u);
  EXPECT_EQ(e[0].name(), "10.0.0.5:3000");
  EXPECT_EQ(e[1].name(), "10.0.0.6:3002");
  EXPECT_EQ(e[2].name(), "host:3000");
  for (const char *bad : {"a,,b", "h:0", "h:70000", ":1", "h:x", ""}) {
    try {
      parse_endpoints(bad, 3000);
      ADD_FAILURE() << bad;
    } catch (const nns::Error &err) {
      EXPECT_NE(std::string(err.what()).find(std::string("dest-host '") + bad + "'"),
                std::string::npos)
          << err.what();
    }
  }
}
