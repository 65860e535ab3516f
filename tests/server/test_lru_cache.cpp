// LruCache, the one cache of the server's model services: what is dropped and when.
#include <gtest/gtest.h>

#include <memory>
#include <string>

#include "server/lru_cache.h"

namespace matlas::server {
namespace {

TEST(LruCache, DropsTheLeastRecentlyUsedBeyondItsCapacity) {
  LruCache<int> cache(2);
  cache.put("a", 1);
  cache.put("b", 2);
  ASSERT_NE(cache.find("a"), nullptr);  // a is now more recent than b
  cache.put("c", 3);
  EXPECT_EQ(cache.size(), 2u);
  EXPECT_TRUE(cache.contains("a"));
  EXPECT_FALSE(cache.contains("b"));
  EXPECT_EQ(*cache.find("c"), 3);
}

TEST(LruCache, PeekingDoesNotCountAsUse) {
  LruCache<int> cache(2);
  cache.put("a", 1);
  cache.put("b", 2);
  ASSERT_NE(cache.peek("a"), nullptr);
  EXPECT_EQ(*cache.peek("a"), 1);
  cache.put("c", 3);
  EXPECT_FALSE(cache.contains("a"));  // still the least recently used
  EXPECT_EQ(cache.peek("a"), nullptr);
}

TEST(LruCache, PinnedKeysStayAndTheNewValueIsNeverTheOneDropped) {
  LruCache<int> cache(1);
  cache.pin("default");
  cache.put("default", 0);
  cache.put("x", 1);  // over capacity, but the pinned key stays and so does the new one
  EXPECT_TRUE(cache.contains("default"));
  EXPECT_TRUE(cache.contains("x"));
  cache.put("y", 2);  // x goes
  EXPECT_TRUE(cache.contains("default"));
  EXPECT_FALSE(cache.contains("x"));
  EXPECT_TRUE(cache.contains("y"));
  EXPECT_EQ(cache.size(), 2u);
}

TEST(LruCache, KeepsOrReplacesAnExistingValue) {
  LruCache<std::shared_ptr<int>> cache(4);
  auto first = std::make_shared<int>(1);
  cache.put("k", first);
  EXPECT_EQ(*cache.put("k", std::make_shared<int>(2), /*keep_existing=*/true), first);  // the first one wins
  EXPECT_EQ(**cache.put("k", std::make_shared<int>(3)), 3);                           // replaced
  EXPECT_EQ(cache.size(), 1u);
}

TEST(LruCache, ACapacityOfZeroKeepsNothing) {
  LruCache<int> cache(0);
  EXPECT_EQ(cache.put("a", 1), nullptr);
  EXPECT_EQ(cache.size(), 0u);
  EXPECT_EQ(cache.find("a"), nullptr);
}

}  // namespace
}  // namespace matlas::server
