// The link's MAC as pure functions: what a tag binds (every header and payload byte, the
// connection's nonces, the direction) and how SessionAuth applies it per frame.
#include <gtest/gtest.h>

#include "link/key_ring.hpp"
#include "link/session_auth.hpp"
#include "meter/protocol/frame_tag.hpp"
#include "test_util.hpp"

namespace meter::protocol {
namespace {

using detail::KeyRing;
using detail::SessionAuth;

FrameKey key_of(int seed) {
  FrameKey k;
  for (std::size_t i = 0; i < k.bytes.size(); ++i) k.bytes[i] = static_cast<std::uint8_t>(seed + i);
  return k;
}

Frame delta_frame(std::uint64_t seq, double speed) {
  return Frame{seq, 1000, Delta{{SignalUpdate{1, SignalStatus::Valid, speed, false, {}}}}};
}

TEST(FrameTag, ATaggedFrameDecodesAndVerifiesOnlyUnderItsKey) {
  const auto key = key_of(1);
  const auto bytes = encode(delta_frame(5, 61.5), &key);
  const auto r = decode(bytes);
  ASSERT_EQ(r.error, DecodeError::None) << r.detail;
  EXPECT_TRUE(r.header.tagged());
  EXPECT_EQ(r.frame_size, bytes.size());
  EXPECT_EQ(r.bytes.size(), bytes.size());
  EXPECT_TRUE(frame_tag_matches(r.bytes, key));
  EXPECT_FALSE(frame_tag_matches(r.bytes, key_of(2)));
  EXPECT_FALSE(frame_tag_matches(encode(delta_frame(5, 61.5)), key));  // untagged: no tag to match
}

TEST(FrameTag, EveryByteOfHeaderPayloadAndTagIsCovered) {
  const auto key = key_of(7);
  const auto bytes = encode(delta_frame(9, 88.0), &key);
  for (std::size_t i = 0; i < bytes.size(); ++i) {
    auto altered = bytes;
    altered[i] ^= 0x01;
    EXPECT_FALSE(frame_tag_matches(altered, key)) << "byte " << i;
  }
}

TEST(FrameTag, SessionKeysDifferByDirectionAndByEitherNonce) {
  const auto k = key_of(3);
  Nonce a{}, b{}, c{};
  a[0] = 1;
  b[0] = 2;
  c[0] = 3;
  const auto pub_ab = derive_session_key(k, Role::Publisher, a, b);
  EXPECT_EQ(pub_ab, derive_session_key(k, Role::Publisher, a, b));
  EXPECT_NE(pub_ab, derive_session_key(k, Role::Subscriber, a, b));
  EXPECT_NE(pub_ab, derive_session_key(k, Role::Publisher, c, b));
  EXPECT_NE(pub_ab, derive_session_key(k, Role::Publisher, a, c));
  EXPECT_NE(pub_ab, derive_session_key(key_of(4), Role::Publisher, a, b));
  EXPECT_NE(derive_hello_key(k, Role::Publisher), derive_hello_key(k, Role::Subscriber));
  EXPECT_NE(fresh_nonce(), fresh_nonce());
}

// Two ends of one connection, without sockets: the HELLOs cross, then frames go both ways.
struct Pair {
  explicit Pair(const KeyRing& pub_keys, const KeyRing& sub_keys)
      : pub(pub_keys, Role::Publisher), sub(sub_keys, Role::Subscriber) {}
  SessionAuth pub, sub;

  static Hello hello(Role role, const SessionAuth& auth) {
    Hello h = test::subscriber_hello();
    h.role = role;
    auth.announce(h);
    return h;
  }
  // Encodes a frame as `from` sends it and checks it as `to` receives it.
  static DecodeError pass(const SessionAuth& from, const SessionAuth& to, const Frame& f,
                          std::vector<std::uint8_t>* keep = nullptr) {
    auto bytes = encode(f, from.tx_key(type_of(f.message)));
    if (keep != nullptr) *keep = bytes;
    return check(to, bytes);
  }
  static DecodeError check(const SessionAuth& to, const std::vector<std::uint8_t>& bytes) {
    const auto r = decode(bytes);
    EXPECT_EQ(r.error, DecodeError::None) << r.detail;
    std::string detail;
    bool fatal = false;
    return to.check(r, detail, fatal);
  }
  void handshake() {
    const Hello ph = hello(Role::Publisher, pub), sh = hello(Role::Subscriber, sub);
    ASSERT_EQ(pass(pub, sub, Frame{1, 0, ph}), DecodeError::None);
    ASSERT_EQ(pass(sub, pub, Frame{1, 0, sh}), DecodeError::None);
    ASSERT_EQ(sub.start(ph), "");
    ASSERT_EQ(pub.start(sh), "");
  }
};

TEST(SessionAuth, FramesVerifyInTheirDirectionOnTheirConnectionOnly) {
  test::TempDir dir;
  const KeyRing keys(test::write_key_file(dir.file("k"), {{1, 10}}));
  Pair first(keys, keys);
  first.handshake();
  std::vector<std::uint8_t> recorded;
  EXPECT_EQ(Pair::pass(first.pub, first.sub, delta_frame(2, 50), &recorded), DecodeError::None);
  EXPECT_EQ(Pair::check(first.pub, recorded), DecodeError::BadMac);  // reflected back to its sender
  EXPECT_EQ(Pair::pass(first.sub, first.pub, Frame{2, 0, Heartbeat{}}), DecodeError::None);

  Pair second(keys, keys);  // a new connection: new nonces, so the recording does not verify
  second.handshake();
  EXPECT_EQ(Pair::check(second.sub, recorded), DecodeError::BadMac);

  auto stripped = encode(delta_frame(3, 50));  // the same DELTA without a MAC: a downgrade
  EXPECT_EQ(Pair::check(first.sub, stripped), DecodeError::MissingMac);
  // A CLOSE may come untagged (it can only end the connection); the link logs it as such.
  EXPECT_EQ(Pair::check(first.sub, encode(Frame{4, 0, Close{CloseReason::Normal, ""}})), DecodeError::None);
}

TEST(SessionAuth, HelloNamesTheKeyAndIsRefusedWhenTheEndsDisagree) {
  test::TempDir dir;
  const KeyRing one(test::write_key_file(dir.file("one"), {{1, 10}}));
  const KeyRing other_bytes(test::write_key_file(dir.file("other"), {{1, 99}}));
  const KeyRing rotated(test::write_key_file(dir.file("rotated"), {{2, 20}, {1, 10}}));
  const KeyRing only_two(test::write_key_file(dir.file("two"), {{2, 20}}));

  // The same id with other bytes: the HELLO's tag fails, and that is fatal.
  SessionAuth pub(one, Role::Publisher), sub(other_bytes, Role::Subscriber);
  const auto hello_bytes = encode(Frame{1, 0, Pair::hello(Role::Publisher, pub)}, pub.tx_key(MessageType::Hello));
  const auto r = decode(hello_bytes);  // r.bytes views hello_bytes
  std::string detail;
  bool fatal = false;
  EXPECT_EQ(sub.check(r, detail, fatal), DecodeError::BadMac);
  EXPECT_TRUE(fatal);
  EXPECT_NE(detail.find("different keys under that id"), std::string::npos) << detail;

  // Rotation in progress: one end tags with key 2, the other with key 1, each holds both.
  Pair mixed(rotated, one);
  EXPECT_NE(mixed.sub.start(Pair::hello(Role::Publisher, mixed.pub)), "");  // "one" lacks key 2
  Pair both(rotated, rotated);
  both.handshake();
  EXPECT_EQ(Pair::pass(both.pub, both.sub, delta_frame(2, 1), nullptr), DecodeError::None);

  SessionAuth lone(only_two, Role::Subscriber);
  const auto why = lone.start(Pair::hello(Role::Publisher, pub));
  EXPECT_NE(why.find("key id 1, which"), std::string::npos) << why;
  EXPECT_NE(why.find("holds 2"), std::string::npos) << why;
  Hello plain = test::subscriber_hello();
  EXPECT_NE(pub.start(plain).find("does not authenticate"), std::string::npos);
  EXPECT_NE(detail::start_session(nullptr, Pair::hello(Role::Publisher, pub)).find("no key file"), std::string::npos);
  EXPECT_EQ(detail::start_session(nullptr, plain), "");
}

}  // namespace
}  // namespace meter::protocol
