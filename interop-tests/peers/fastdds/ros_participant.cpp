// An independent DDS peer (eProsima Fast DDS 2.9, the DDS of rmw_fastrtps_cpp) that joins the
// ROS 2 Jazzy graph as an rmw_fastrtps_cpp participant would:
//
// * one DomainParticipant whose USER_DATA is `enclave=/;` plus the terminating NUL, exactly as
//   rmw_fastrtps_shared_cpp `participant.cpp` (jazzy) writes it (`snprintf` into a buffer sized
//   `strlen + 1`), and whose name is the enclave;
// * a `ros_discovery_info` writer (RELIABLE, TRANSIENT_LOCAL, KEEP_LAST 1) and reader (RELIABLE,
//   TRANSIENT_LOCAL, KEEP_ALL) of `rmw_dds_common::msg::dds_::ParticipantEntitiesInfo_`
//   (rmw_dds_common `qos.cpp` / rmw_fastrtps_shared_cpp `init_rmw_context_impl.cpp`);
// * a node NAMESPACE/NODE announced there, republished whenever its endpoints change;
// * a service server for SERVICE (`example_interfaces/srv/AddTwoInts`): a reader on
//   `rq<SERVICE>Request` and a writer on `rr<SERVICE>Reply`, and a client for the same service
//   (writer on rq, reader on rr), all with rmw_qos_profile_services_default mapped the way
//   rmw_fastrtps_shared_cpp `qos.cpp` does (RELIABLE, VOLATILE, KEEP_LAST 10, XCDR1
//   representation, USER_DATA `typehash=RIHS01_<hex>;` without a NUL, from rmw_dds_common
//   `encode_type_hash_for_user_data_qos`), memory policy PREALLOCATED_WITH_REALLOC and data
//   sharing off (rmw_fastrtps_cpp `rmw_service.cpp`, `rmw_client.cpp`);
// * the server answers requests as rmw_fastrtps does (`rmw_request.cpp` `__rmw_take_request`,
//   `rmw_response.cpp` `__rmw_send_response`): the request id is the request's sample identity
//   with its GUID replaced by the related_sample_identity GUID when one is given; the reply
//   carries that id as its related_sample_identity, after waiting (at most the reply writer's
//   reliability max_blocking_time) for the client's reply reader to match when that GUID is a
//   reader -- and is not sent at all if it does not match in time (RMW_RET_TIMEOUT there);
// * the client calls as rmw_fastrtps does: it waits until the server is available the way
//   `rmw_service_server_is_available.cpp` decides (readers on the request topic and writers on
//   the reply topic known from discovery, as many of each, and the client's request writer and
//   reply reader matched with as many endpoints, at least one), writes each request with
//   WriteParams related_sample_identity = {its reply reader's GUID, SN unknown} and takes the
//   sequence number Fast DDS assigned the sample as the request's (`__rmw_send_request`), and
//   accepts a reply iff its related_sample_identity GUID is its reply reader's or request
//   writer's, reading the request's sequence number from it (`__rmw_take_response`).
//
// Serving (the default mode): it prints ONE JSON line on stdout describing what it created,
// lingers LINGER seconds answering requests -- printing one line `{"served": {...}}` per request
// taken, with the request id it computed -- then removes its node (republishing
// ros_discovery_info) and deletes every entity so that peers see them leave.
//
// Calling (`call COUNT`): its node has only the client. It prints the same first line (with
// `"server": null`), waits for a server, sends COUNT requests one after the other (a = i,
// b = 10 * i for i = 1..COUNT), printing `{"a", "b", "sum", "sequence_number"}` per reply and a
// final `{"summary": {...}}` line, all within LINGER seconds; then leaves as above. Exit status 0
// iff all COUNT replies arrived with the right sums, else 1.
//
// Chatter (`talk COUNT` / `listen COUNT`, with TOPIC in place of SERVICE): its node is a
// demo_nodes_cpp talker or listener on rmw_fastrtps_cpp -- one writer (talk) or reader (listen)
// on `rt<TOPIC>` of `std_msgs::msg::dds_::String_`, with rclcpp's default QoS (KEEP_LAST 10,
// RELIABLE, VOLATILE) mapped as rmw_fastrtps_cpp `publisher.cpp` / `subscription.cpp` (jazzy)
// do: the same QoS as the service endpoints above, std_msgs/msg/String's type hash in USER_DATA.
// It prints the same kind of first line (`"mode": "talk"` / `"listen"`, `"topic"`, `"type"`,
// `"writer"` or `"reader"`, `"qos"`). The talker then publishes `Hello World: <n>` (n = 1, 2, …)
// every 50 ms (demo_nodes_cpp's talker: every second), printing `{"published": "<data>"}` per
// message, until COUNT were published (0: no limit), LINGER is over or SIGTERM; the listener
// prints `{"heard": "<data>", "writer": "<GID>"}` per message taken until it heard COUNT (0: no
// limit), LINGER is over or SIGTERM. Then it leaves as above. Exit status 0 iff the listener
// heard COUNT messages (always 0 for the talker).
//
// usage: ros_participant DOMAIN NAMESPACE NODE SERVICE LINGER [call COUNT]
//        ros_participant DOMAIN NAMESPACE NODE TOPIC LINGER talk|listen COUNT
//   SERVICE and TOPIC are fully qualified names (`/add_two_ints`, `/chatter`).

#include <chrono>
#include <csignal>
#include <cinttypes>
#include <condition_variable>
#include <map>
#include <mutex>
#include <set>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <functional>
#include <memory>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include <fastcdr/Cdr.h>
#include <fastcdr/FastBuffer.h>
#include <fastdds/dds/core/status/StatusMask.hpp>
#include <fastdds/dds/domain/DomainParticipant.hpp>
#include <fastdds/dds/domain/DomainParticipantFactory.hpp>
#include <fastdds/dds/domain/DomainParticipantListener.hpp>
#include <fastdds/dds/domain/qos/DomainParticipantQos.hpp>
#include <fastdds/dds/publisher/DataWriter.hpp>
#include <fastdds/dds/publisher/DataWriterListener.hpp>
#include <fastdds/dds/publisher/Publisher.hpp>
#include <fastdds/dds/publisher/qos/DataWriterQos.hpp>
#include <fastdds/dds/subscriber/DataReader.hpp>
#include <fastdds/dds/subscriber/DataReaderListener.hpp>
#include <fastdds/dds/subscriber/SampleInfo.hpp>
#include <fastdds/dds/subscriber/Subscriber.hpp>
#include <fastdds/dds/subscriber/qos/DataReaderQos.hpp>
#include <fastdds/dds/topic/Topic.hpp>
#include <fastdds/dds/topic/TopicDataType.hpp>
#include <fastdds/dds/topic/TypeSupport.hpp>
#include <fastdds/rtps/common/InstanceHandle.h>
#include <fastdds/rtps/common/WriteParams.h>
#include <fastdds/rtps/transport/UDPv4TransportDescriptor.h>

using eprosima::fastdds::dds::DataReader;
using eprosima::fastdds::dds::DataReaderQos;
using eprosima::fastdds::dds::DataWriter;
using eprosima::fastdds::dds::DataWriterQos;
using eprosima::fastdds::dds::DomainParticipant;
using eprosima::fastdds::dds::DomainParticipantFactory;
using eprosima::fastdds::dds::DomainParticipantListener;
using eprosima::fastdds::dds::DomainParticipantQos;
using eprosima::fastdds::dds::Publisher;
using eprosima::fastdds::dds::SampleInfo;
using eprosima::fastdds::dds::Subscriber;
using eprosima::fastdds::dds::Topic;
using eprosima::fastdds::dds::TopicDataType;
using eprosima::fastdds::dds::TypeSupport;
using eprosima::fastrtps::rtps::GUID_t;
using eprosima::fastrtps::rtps::InstanceHandle_t;
using eprosima::fastrtps::rtps::SampleIdentity;
using eprosima::fastrtps::rtps::SequenceNumber_t;
using eprosima::fastrtps::rtps::SerializedPayload_t;
using eprosima::fastrtps::rtps::WriteParams;
using ReturnCode_t = eprosima::fastrtps::types::ReturnCode_t;

namespace {

// REP-2011 hashes of the request and response types, from a Jazzy build's type descriptions.
const char * const REQUEST_HASH =
  "RIHS01_000c5fd92d6b2e1a05949348f584d6d652adea1e92d691792011ac2273508302";
const char * const RESPONSE_HASH =
  "RIHS01_de5c030d4af33cba2749310b249737b631594703f9300495f48bffb2b44dcc2f";
// std_msgs/msg/String's (the msgs crate's test vectors, msgs/tests/hashes.rs).
const char * const STRING_HASH =
  "RIHS01_df668c740482bbd48fb39d76a70dfd4bd59db1288021743503259e948f6b1a18";

// ---------------------------------------------------------------------------------------------
// Message types (rmw_dds_common jazzy msg/*.msg; example_interfaces srv/AddTwoInts.srv)

struct Gid
{
  uint8_t data[16];  // rmw_dds_common/msg/Gid.msg: char[16] data (Jazzy)
};

struct NodeEntitiesInfo
{
  std::string node_namespace;
  std::string node_name;
  std::vector<Gid> reader_gid_seq;
  std::vector<Gid> writer_gid_seq;
};

struct ParticipantEntitiesInfo
{
  Gid gid;
  std::vector<NodeEntitiesInfo> node_entities_info_seq;
};

struct AddTwoIntsRequest
{
  int64_t a = 0;
  int64_t b = 0;
};

struct AddTwoIntsResponse
{
  int64_t sum = 0;
};

struct StringMsg
{
  std::string data;  // std_msgs/msg/String.msg: string data
};

void serialize_gid(eprosima::fastcdr::Cdr & cdr, const Gid & gid)
{
  for (uint8_t byte : gid.data) {
    cdr.serialize(byte);
  }
}

void deserialize_gid(eprosima::fastcdr::Cdr & cdr, Gid & gid)
{
  for (uint8_t & byte : gid.data) {
    cdr.deserialize(byte);
  }
}

void serialize(eprosima::fastcdr::Cdr & cdr, const ParticipantEntitiesInfo & m)
{
  serialize_gid(cdr, m.gid);
  cdr.serialize(static_cast<uint32_t>(m.node_entities_info_seq.size()));
  for (const auto & node : m.node_entities_info_seq) {
    cdr.serialize(node.node_namespace);
    cdr.serialize(node.node_name);
    cdr.serialize(static_cast<uint32_t>(node.reader_gid_seq.size()));
    for (const auto & g : node.reader_gid_seq) {
      serialize_gid(cdr, g);
    }
    cdr.serialize(static_cast<uint32_t>(node.writer_gid_seq.size()));
    for (const auto & g : node.writer_gid_seq) {
      serialize_gid(cdr, g);
    }
  }
}

void deserialize_gids(eprosima::fastcdr::Cdr & cdr, std::vector<Gid> & gids)
{
  uint32_t n = 0;
  cdr.deserialize(n);
  gids.resize(n);
  for (auto & g : gids) {
    deserialize_gid(cdr, g);
  }
}

void deserialize(eprosima::fastcdr::Cdr & cdr, ParticipantEntitiesInfo & m)
{
  deserialize_gid(cdr, m.gid);
  uint32_t n = 0;
  cdr.deserialize(n);
  m.node_entities_info_seq.resize(n);
  for (auto & node : m.node_entities_info_seq) {
    cdr.deserialize(node.node_namespace);
    cdr.deserialize(node.node_name);
    deserialize_gids(cdr, node.reader_gid_seq);
    deserialize_gids(cdr, node.writer_gid_seq);
  }
}

// An upper bound of the XCDR1 size of the body starting at offset 4 (after the encapsulation).
size_t serialized_size(const ParticipantEntitiesInfo & m)
{
  size_t size = 16 + 4;
  for (const auto & node : m.node_entities_info_seq) {
    size += 3 + 4 + node.node_namespace.size() + 1;
    size += 3 + 4 + node.node_name.size() + 1;
    size += 3 + 4 + 16 * node.reader_gid_seq.size();
    size += 3 + 4 + 16 * node.writer_gid_seq.size();
  }
  return size;
}

void serialize(eprosima::fastcdr::Cdr & cdr, const AddTwoIntsRequest & m)
{
  cdr.serialize(m.a);
  cdr.serialize(m.b);
}
void deserialize(eprosima::fastcdr::Cdr & cdr, AddTwoIntsRequest & m)
{
  cdr.deserialize(m.a);
  cdr.deserialize(m.b);
}
size_t serialized_size(const AddTwoIntsRequest &) {return 16;}

void serialize(eprosima::fastcdr::Cdr & cdr, const AddTwoIntsResponse & m) {cdr.serialize(m.sum);}
void deserialize(eprosima::fastcdr::Cdr & cdr, AddTwoIntsResponse & m) {cdr.deserialize(m.sum);}
size_t serialized_size(const AddTwoIntsResponse &) {return 8;}

void serialize(eprosima::fastcdr::Cdr & cdr, const StringMsg & m) {cdr.serialize(m.data);}
void deserialize(eprosima::fastcdr::Cdr & cdr, StringMsg & m) {cdr.deserialize(m.data);}
size_t serialized_size(const StringMsg & m) {return 4 + m.data.size() + 1;}

// A keyless TopicDataType writing XCDR1 with the encapsulation header, the way the
// rmw_fastrtps_shared_cpp TypeSupport does (`TypeSupport_impl.cpp`: DDS_CDR, DEFAULT_ENDIAN,
// no type object / type information).
template<typename T>
class RosType : public TopicDataType
{
public:
  RosType(const char * name, uint32_t max_size)
  {
    setName(name);
    m_typeSize = max_size + 4;
    m_isGetKeyDefined = false;
    auto_fill_type_object(false);
    auto_fill_type_information(false);
  }

  bool serialize(void * data, SerializedPayload_t * payload) override
  {
    const T * m = static_cast<const T *>(data);
    eprosima::fastcdr::FastBuffer buffer(reinterpret_cast<char *>(payload->data), payload->max_size);
    eprosima::fastcdr::Cdr cdr(
      buffer, eprosima::fastcdr::Cdr::DEFAULT_ENDIAN, eprosima::fastcdr::Cdr::DDS_CDR);
    payload->encapsulation =
      cdr.endianness() == eprosima::fastcdr::Cdr::BIG_ENDIANNESS ? CDR_BE : CDR_LE;
    try {
      cdr.serialize_encapsulation();
      ::serialize(cdr, *m);
    } catch (const std::exception &) {
      return false;
    }
    payload->length = static_cast<uint32_t>(cdr.getSerializedDataLength());
    return true;
  }

  bool deserialize(SerializedPayload_t * payload, void * data) override
  {
    T * m = static_cast<T *>(data);
    eprosima::fastcdr::FastBuffer buffer(reinterpret_cast<char *>(payload->data), payload->length);
    eprosima::fastcdr::Cdr cdr(
      buffer, eprosima::fastcdr::Cdr::DEFAULT_ENDIAN, eprosima::fastcdr::Cdr::DDS_CDR);
    try {
      cdr.read_encapsulation();
      payload->encapsulation =
        cdr.endianness() == eprosima::fastcdr::Cdr::BIG_ENDIANNESS ? CDR_BE : CDR_LE;
      ::deserialize(cdr, *m);
    } catch (const std::exception &) {
      return false;
    }
    return true;
  }

  std::function<uint32_t()> getSerializedSizeProvider(void * data) override
  {
    return [data]() {
             return static_cast<uint32_t>(4 + ::serialized_size(*static_cast<const T *>(data)));
           };
  }

  void * createData() override {return new T();}
  void deleteData(void * data) override {delete static_cast<T *>(data);}
  bool getKey(void *, InstanceHandle_t *, bool) override {return false;}
};

// ---------------------------------------------------------------------------------------------

Gid to_gid(const GUID_t & guid)
{
  // rmw_fastrtps_shared_cpp `guid_utils.hpp` copy_from_fastrtps_guid_to_byte_array: prefix then
  // entity id, 16 bytes.
  Gid gid{};
  std::memcpy(gid.data, guid.guidPrefix.value, 12);
  std::memcpy(gid.data + 12, guid.entityId.value, 4);
  return gid;
}

std::string dotted(const Gid & gid)
{
  std::string out;
  char buf[4];
  for (size_t i = 0; i < 16; ++i) {
    std::snprintf(buf, sizeof buf, i == 0 ? "%02x" : ".%02x", gid.data[i]);
    out += buf;
  }
  return out;
}

std::string json_string(const std::string & s)
{
  std::string out = "\"";
  for (char c : s) {
    if (c == '"' || c == '\\') {
      out += '\\';
      out += c;
    } else if (static_cast<unsigned char>(c) < 0x20) {
      char buf[8];
      std::snprintf(buf, sizeof buf, "\\u%04x", c);
      out += buf;
    } else {
      out += c;
    }
  }
  return out + "\"";
}

template<typename EntityQos>
std::string qos_json(const EntityQos & qos)
{
  using namespace eprosima::fastdds::dds;
  std::ostringstream out;
  out << "{\"reliability\": \""
      << (qos.reliability().kind == RELIABLE_RELIABILITY_QOS ? "RELIABLE" : "BEST_EFFORT")
      << "\", \"durability\": \"";
  switch (qos.durability().kind) {
    case VOLATILE_DURABILITY_QOS: out << "VOLATILE"; break;
    case TRANSIENT_LOCAL_DURABILITY_QOS: out << "TRANSIENT_LOCAL"; break;
    case TRANSIENT_DURABILITY_QOS: out << "TRANSIENT"; break;
    default: out << "PERSISTENT"; break;
  }
  out << "\", \"history\": \""
      << (qos.history().kind == KEEP_LAST_HISTORY_QOS ? "KEEP_LAST" : "KEEP_ALL")
      << "\", \"depth\": " << qos.history().depth << "}";
  return out.str();
}

std::vector<eprosima::fastrtps::rtps::octet> octets(const std::string & s)
{
  return std::vector<eprosima::fastrtps::rtps::octet>(s.begin(), s.end());
}

// rmw_qos_profile_services_default (KEEP_LAST 10, RELIABLE, VOLATILE) as rmw_fastrtps_shared_cpp
// `qos.cpp` fills a DataReader/DataWriter QoS, plus what `rmw_service.cpp` / `rmw_client.cpp`
// change when RMW_FASTRTPS_USE_QOS_FROM_XML is unset.
template<typename EntityQos>
void services_default(EntityQos & qos, const char * type_hash)
{
  using namespace eprosima::fastdds::dds;
  qos.history().kind = KEEP_LAST_HISTORY_QOS;
  if (qos.history().depth < 10) {
    qos.history().depth = 10;
  }
  qos.durability().kind = VOLATILE_DURABILITY_QOS;
  qos.reliability().kind = RELIABLE_RELIABILITY_QOS;
  qos.user_data().setValue(octets(std::string("typehash=") + type_hash + ";"));
  qos.endpoint().history_memory_policy =
    eprosima::fastrtps::rtps::PREALLOCATED_WITH_REALLOC_MEMORY_MODE;
  qos.data_sharing().off();
}

DataReaderQos service_reader_qos(Subscriber * subscriber, const char * type_hash)
{
  DataReaderQos qos = subscriber->get_default_datareader_qos();
  services_default(qos, type_hash);
  qos.type_consistency().representation.clear();
  qos.type_consistency().representation.m_value.push_back(
    eprosima::fastdds::dds::XCDR_DATA_REPRESENTATION);
  return qos;
}

DataWriterQos service_writer_qos(Publisher * publisher, const char * type_hash)
{
  DataWriterQos qos = publisher->get_default_datawriter_qos();
  services_default(qos, type_hash);
  qos.publish_mode().kind = eprosima::fastdds::dds::SYNCHRONOUS_PUBLISH_MODE;
  qos.representation().clear();
  qos.representation().m_value.push_back(eprosima::fastdds::dds::XCDR_DATA_REPRESENTATION);
  return qos;
}

// The endpoints a writer or reader is matched with, kept from on_publication_matched /
// on_subscription_matched the way rmw_fastrtps' listeners keep them (`custom_service_info.hpp`
// ServicePubListener, `custom_client_info.hpp` ClientListener / ClientPubListener): Fast DDS 2.9
// does not implement DataWriter::get_matched_subscriptions / DataReader::get_matched_publications
// (they return RETCODE_UNSUPPORTED).
class Matches
{
public:
  void update(const InstanceHandle_t & handle, int32_t change)
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (change == 1) {
      matched_.insert(eprosima::fastrtps::rtps::iHandle2GUID(handle));
    } else if (change == -1) {
      matched_.erase(eprosima::fastrtps::rtps::iHandle2GUID(handle));
    } else {
      return;
    }
    cv_.notify_all();
  }

  size_t count() const
  {
    std::lock_guard<std::mutex> lock(mutex_);
    return matched_.size();
  }

  // ServicePubListener::wait_for_subscription
  bool wait_for(const GUID_t & guid, std::chrono::nanoseconds limit)
  {
    std::unique_lock<std::mutex> lock(mutex_);
    return cv_.wait_for(lock, limit, [&]() {return matched_.count(guid) != 0;});
  }

private:
  mutable std::mutex mutex_;
  std::condition_variable cv_;
  std::set<GUID_t> matched_;
};

class WriterMatches : public eprosima::fastdds::dds::DataWriterListener, public Matches
{
public:
  void on_publication_matched(
    DataWriter *, const eprosima::fastdds::dds::PublicationMatchedStatus & status) override
  {
    update(status.last_subscription_handle, status.current_count_change);
  }
};

class ReaderMatches : public eprosima::fastdds::dds::DataReaderListener, public Matches
{
public:
  void on_subscription_matched(
    DataReader *, const eprosima::fastdds::dds::SubscriptionMatchedStatus & status) override
  {
    update(status.last_publication_handle, status.current_count_change);
  }
};

int64_t to_int64(const SequenceNumber_t & sn)
{
  // rmw_fastrtps: ((int64_t)high) << 32 | low
  return (static_cast<int64_t>(sn.high) << 32) | sn.low;
}

std::string identity_json(const SampleIdentity & id)
{
  std::ostringstream out;
  out << "{\"writer_guid\": " << json_string(dotted(to_gid(id.writer_guid())))
      << ", \"sequence_number\": " << to_int64(id.sequence_number()) << "}";
  return out.str();
}

void print_line(const std::string & line)
{
  std::printf("%s\n", line.c_str());
  std::fflush(stdout);
}

// Answers every waiting request, as rmw_fastrtps `__rmw_take_request` + `__rmw_send_response`,
// printing one line per request taken.
void serve(DataReader * requests, DataWriter * replies, WriterMatches & reply_matches)
{
  AddTwoIntsRequest request;
  SampleInfo info;
  while (requests->take_next_sample(&request, &info) == ReturnCode_t::RETCODE_OK) {
    if (!info.valid_data) {
      continue;
    }
    // __rmw_take_request: the request id is the sample identity, its GUID replaced by the
    // related_sample_identity GUID (the client's reply reader) when present.
    SampleIdentity id = info.sample_identity;
    const GUID_t & related = info.related_sample_identity.writer_guid();
    if (related != GUID_t::unknown()) {
      id.writer_guid() = related;
    }
    AddTwoIntsResponse response;
    response.sum = request.a + request.b;
    // __rmw_send_response: reply with related_sample_identity = the request id. An entity id
    // whose kind has bit 0x04 set is a reader (the client's reply reader): first wait, at most
    // the reply writer's reliability max_blocking_time, for our reply writer to match it; if it
    // does not, rmw_fastrtps returns RMW_RET_TIMEOUT without sending.
    const char * client_present = "UNCHECKED";
    bool send = true;
    if ((id.writer_guid().entityId.value[3] & 0x04) != 0) {
      const auto & blocking = replies->get_qos().reliability().max_blocking_time;
      const bool matched = reply_matches.wait_for(
        id.writer_guid(),
        std::chrono::seconds(blocking.seconds) + std::chrono::nanoseconds(blocking.nanosec));
      client_present = matched ? "YES" : "MAYBE";
      send = matched;
    }
    bool sent = false;
    if (send) {
      WriteParams params;
      params.related_sample_identity(id);
      sent = replies->write(&response, params);
      if (!sent) {
        std::fprintf(stderr, "ros_participant: could not write a reply\n");
      }
    }
    std::ostringstream line;
    line << "{\"served\": {\"a\": " << request.a << ", \"b\": " << request.b
         << ", \"sum\": " << response.sum
         << ", \"request_id\": " << identity_json(id)
         << ", \"sample_identity\": " << identity_json(info.sample_identity)
         << ", \"related_sample_identity\": " << identity_json(info.related_sample_identity)
         << ", \"client_present\": \"" << client_present << "\""
         << ", \"sent\": " << (sent ? "true" : "false") << "}}";
    print_line(line.str());
  }
}

// What rmw_fastrtps' participant listener feeds into its graph cache (custom_participant_info.hpp
// `process_discovery_info`): the endpoints discovered, by topic.
class GraphListener : public DomainParticipantListener
{
public:
  void on_subscriber_discovery(
    DomainParticipant *, eprosima::fastrtps::rtps::ReaderDiscoveryInfo && info) override
  {
    using Status = eprosima::fastrtps::rtps::ReaderDiscoveryInfo;
    if (info.status != Status::CHANGED_QOS_READER) {
      update(readers_, info.info.topicName().to_string(), info.info.guid(),
        info.status == Status::DISCOVERED_READER);
    }
  }

  void on_publisher_discovery(
    DomainParticipant *, eprosima::fastrtps::rtps::WriterDiscoveryInfo && info) override
  {
    using Status = eprosima::fastrtps::rtps::WriterDiscoveryInfo;
    if (info.status != Status::CHANGED_QOS_WRITER) {
      update(writers_, info.info.topicName().to_string(), info.info.guid(),
        info.status == Status::DISCOVERED_WRITER);
    }
  }

  // graph_cache.get_reader_count / get_writer_count
  size_t reader_count(const std::string & topic) const {return count(readers_, topic);}
  size_t writer_count(const std::string & topic) const {return count(writers_, topic);}

private:
  using ByTopic = std::map<std::string, std::set<GUID_t>>;

  void update(ByTopic & map, const std::string & topic, const GUID_t & guid, bool alive)
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (alive) {
      map[topic].insert(guid);
    } else {
      map[topic].erase(guid);
    }
  }

  size_t count(const ByTopic & map, const std::string & topic) const
  {
    std::lock_guard<std::mutex> lock(mutex_);
    auto it = map.find(topic);
    return it == map.end() ? 0 : it->second.size();
  }

  mutable std::mutex mutex_;
  ByTopic readers_;
  ByTopic writers_;
};

// rmw_fastrtps_shared_cpp `__rmw_service_server_is_available` for a client with these endpoints.
// The matched counts are those rmw's client listeners keep (request_publisher_matched_count_,
// response_subscriber_matched_count_).
bool server_is_available(
  const GraphListener & graph, const std::string & request_topic,
  const std::string & reply_topic, const Matches & request_matches,
  const Matches & reply_matches)
{
  size_t request_subscribers = graph.reader_count(request_topic);
  if (request_subscribers == 0) {
    return false;
  }
  size_t response_publishers = graph.writer_count(reply_topic);
  if (response_publishers == 0 || request_subscribers != response_publishers) {
    return false;
  }
  const size_t matched_request_pubs = request_matches.count();
  const size_t matched_response_subs = reply_matches.count();
  return matched_request_pubs != 0 && matched_response_subs != 0 &&
         matched_request_pubs == matched_response_subs;
}

// The client side: waits for a server, then calls COUNT times, one after the other, as rclcpp
// over rmw_fastrtps would (`__rmw_send_request`, `__rmw_take_response`). True iff every reply
// arrived before `deadline` with the right sum.
bool call(
  const GraphListener & graph, const std::string & request_topic,
  const std::string & reply_topic, DataWriter * request_writer, DataReader * reply_reader,
  const Matches & request_matches, const Matches & reply_matches, long count,
  std::chrono::steady_clock::time_point deadline)
{
  using Clock = std::chrono::steady_clock;
  const auto started = Clock::now();
  bool available = false;
  while (!(available =
    server_is_available(graph, request_topic, reply_topic, request_matches, reply_matches)) &&
    Clock::now() < deadline)
  {
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  const auto available_ms =
    std::chrono::duration_cast<std::chrono::milliseconds>(Clock::now() - started).count();
  const GUID_t reader_guid = reply_reader->guid();
  const GUID_t writer_guid = request_writer->guid();
  long correct = 0;
  long answered = 0;
  for (long i = 1; available && i <= count && Clock::now() < deadline; ++i) {
    AddTwoIntsRequest request;
    request.a = i;
    request.b = 10 * i;
    // __rmw_send_request
    WriteParams wparams;
    wparams.related_sample_identity().writer_guid() = reader_guid;
    if (!request_writer->write(&request, wparams)) {
      std::fprintf(stderr, "ros_participant: could not write request %ld\n", i);
      break;
    }
    const int64_t sequence_id = to_int64(wparams.sample_identity().sequence_number());
    // __rmw_take_response, until the reply to this request comes (rclcpp drops replies to
    // sequence numbers it is not waiting for).
    bool got = false;
    AddTwoIntsResponse response;
    while (!got && Clock::now() < deadline) {
      reply_reader->wait_for_unread_message(eprosima::fastrtps::Duration_t(0, 20000000));
      SampleInfo info;
      while (!got && reply_reader->take_next_sample(&response, &info) == ReturnCode_t::RETCODE_OK) {
        if (!info.valid_data) {
          continue;
        }
        const SampleIdentity & related = info.related_sample_identity;
        if (related.writer_guid() != reader_guid && related.writer_guid() != writer_guid) {
          continue;  // not ours
        }
        got = to_int64(related.sequence_number()) == sequence_id;
      }
    }
    if (!got) {
      std::fprintf(stderr, "ros_participant: no reply to request %ld (sequence number %" PRId64
        ")\n", i, sequence_id);
      break;
    }
    ++answered;
    if (response.sum == request.a + request.b) {
      ++correct;
    }
    std::ostringstream line;
    line << "{\"a\": " << request.a << ", \"b\": " << request.b << ", \"sum\": " << response.sum
         << ", \"sequence_number\": " << sequence_id << "}";
    print_line(line.str());
  }
  std::ostringstream line;
  line << "{\"summary\": {\"calls\": " << count << ", \"answered\": " << answered
       << ", \"correct\": " << correct << ", \"available\": " << (available ? "true" : "false")
       << ", \"available_after_ms\": " << available_ms << "}}";
  print_line(line.str());
  return available && correct == count;
}

}  // namespace

// Set by SIGTERM: leave now, as rmw does (see the end of main).
static volatile std::sig_atomic_t g_leave = 0;

static void on_sigterm(int)
{
  g_leave = 1;
}

// The chatter modes' node: a demo_nodes_cpp talker (`talking`) or listener on `rt<topic>`,
// created as rmw_fastrtps_cpp creates a publisher / subscription (then announced in `info`'s
// node through `publish_info`). Prints the first line, then publishes or listens until `count`
// (0: no limit), `end` or SIGTERM. True unless listening and fewer than `count` were heard.
static bool chatter(
  DomainParticipant * participant, Publisher * publisher, Subscriber * subscriber,
  ParticipantEntitiesInfo & info, const std::function<void()> & publish_info,
  const std::string & topic, bool talking, long count,
  std::chrono::steady_clock::time_point end)
{
  using Clock = std::chrono::steady_clock;
  TypeSupport string_type(new RosType<StringMsg>("std_msgs::msg::dds_::String_", 4096));
  string_type.register_type(participant);
  // rmw_fastrtps_shared_cpp `namespace_prefix.cpp`: topics get the `rt` prefix.
  const std::string topic_name = "rt" + topic;
  Topic * dds_topic = participant->create_topic(
    topic_name, string_type.get_type_name(), participant->get_default_topic_qos());
  if (dds_topic == nullptr) {
    std::fprintf(stderr, "ros_participant: could not create the topic %s\n", topic_name.c_str());
    return false;
  }
  // rclcpp's default QoS (rmw_qos_profile_default: KEEP_LAST 10, RELIABLE, VOLATILE), as
  // rmw_fastrtps_cpp `publisher.cpp` / `subscription.cpp` (jazzy) set it with
  // RMW_FASTRTPS_USE_QOS_FROM_XML unset: PREALLOCATED_WITH_REALLOC, no data sharing, the
  // participant's publishing mode (SYNCHRONOUS unless RMW_FASTRTPS_PUBLICATION_MODE says
  // otherwise, rmw_fastrtps_shared_cpp `participant.cpp`), then `get_datawriter_qos` /
  // `get_datareader_qos` (XCDR1, typehash USER_DATA): what the service endpoints get too.
  DataWriter * writer = nullptr;
  DataReader * reader = nullptr;
  std::string endpoint;
  if (talking) {
    writer = publisher->create_datawriter(dds_topic, service_writer_qos(publisher, STRING_HASH));
    if (writer != nullptr) {
      info.node_entities_info_seq[0].writer_gid_seq.push_back(to_gid(writer->guid()));
      endpoint = "\"writer\": " + json_string(dotted(to_gid(writer->guid()))) +
        ", \"qos\": " + qos_json(writer->get_qos());
    }
  } else {
    reader =
      subscriber->create_datareader(dds_topic, service_reader_qos(subscriber, STRING_HASH));
    if (reader != nullptr) {
      info.node_entities_info_seq[0].reader_gid_seq.push_back(to_gid(reader->guid()));
      endpoint = "\"reader\": " + json_string(dotted(to_gid(reader->guid()))) +
        ", \"qos\": " + qos_json(reader->get_qos());
    }
  }
  if (writer == nullptr && reader == nullptr) {
    std::fprintf(stderr, "ros_participant: could not create the %s\n",
      talking ? "publisher" : "subscription");
    return false;
  }
  publish_info();

  const NodeEntitiesInfo & node = info.node_entities_info_seq[0];
  std::ostringstream line;
  line << "{\"participant\": " << json_string(dotted(info.gid))
       << ", \"vendor\": \"010f\""
       << ", \"mode\": \"" << (talking ? "talk" : "listen") << "\""
       << ", \"node\": {\"namespace\": " << json_string(node.node_namespace)
       << ", \"name\": " << json_string(node.node_name) << "}"
       << ", \"topic\": " << json_string(topic_name)
       << ", \"type\": " << json_string(string_type.get_type_name())
       << ", " << endpoint << "}";
  print_line(line.str());

  long done = 0;
  if (talking) {
    // demo_nodes_cpp `talker.cpp`: "Hello World: " + count, count starting at 1. The period is
    // a publishing rate, not a synchronisation: the listener side waits for what it hears.
    auto next = Clock::now();
    while (Clock::now() < end && !g_leave && (count == 0 || done < count)) {
      StringMsg message;
      message.data = "Hello World: " + std::to_string(done + 1);
      if (!writer->write(&message)) {
        std::fprintf(stderr, "ros_participant: could not publish\n");
        return false;
      }
      ++done;
      print_line("{\"published\": " + json_string(message.data) + "}");
      next += std::chrono::milliseconds(50);
      std::this_thread::sleep_until(next);
    }
    return true;
  }
  while (Clock::now() < end && !g_leave && (count == 0 || done < count)) {
    reader->wait_for_unread_message(eprosima::fastrtps::Duration_t(0, 50000000));
    StringMsg message;
    SampleInfo sample;
    while ((count == 0 || done < count) &&
      reader->take_next_sample(&message, &sample) == ReturnCode_t::RETCODE_OK)
    {
      if (!sample.valid_data) {
        continue;
      }
      ++done;
      print_line(
        "{\"heard\": " + json_string(message.data) + ", \"writer\": " +
        json_string(dotted(to_gid(eprosima::fastrtps::rtps::iHandle2GUID(
          sample.publication_handle)))) + "}");
    }
  }
  return count == 0 || done >= count;
}

int main(int argc, char ** argv)
{
  std::signal(SIGTERM, on_sigterm);
  const bool calling = argc == 8 && std::strcmp(argv[6], "call") == 0;
  const bool talking = argc == 8 && std::strcmp(argv[6], "talk") == 0;
  const bool listening = argc == 8 && std::strcmp(argv[6], "listen") == 0;
  if (argc != 6 && !calling && !talking && !listening) {
    std::fprintf(
      stderr, "usage: %s DOMAIN NAMESPACE NODE SERVICE LINGER [call COUNT]\n"
      "       %s DOMAIN NAMESPACE NODE TOPIC LINGER talk|listen COUNT\n", argv[0], argv[0]);
    return 2;
  }
  const long count = argc == 8 ? std::strtol(argv[7], nullptr, 10) : 0;
  if (calling && count < 1) {
    std::fprintf(stderr, "ros_participant: COUNT must be at least 1\n");
    return 2;
  }
  if (count < 0) {
    std::fprintf(stderr, "ros_participant: COUNT must not be negative\n");
    return 2;
  }
  const uint32_t domain = static_cast<uint32_t>(std::strtoul(argv[1], nullptr, 10));
  const std::string node_namespace = argv[2];
  const std::string node_name = argv[3];
  const std::string service = argv[4];
  const double linger = std::strtod(argv[5], nullptr);

  auto factory = DomainParticipantFactory::get_instance();
  DomainParticipantQos pqos = factory->get_default_participant_qos();
  // Loopback only: one UDPv4 transport restricted to 127.0.0.1, no shared memory. Discovery
  // keeps Fast DDS's defaults (SPDP multicast 239.255.0.1, port 7400 + 250 * domain).
  auto udp = std::make_shared<eprosima::fastdds::rtps::UDPv4TransportDescriptor>();
  udp->interfaceWhiteList.emplace_back("127.0.0.1");
  pqos.transport().use_builtin_transports = false;
  pqos.transport().user_transports.push_back(udp);
  // rmw_fastrtps_shared_cpp `participant.cpp`: "enclave=%s;" written with snprintf into a
  // buffer of strlen + 1 bytes, so USER_DATA ends with the NUL.
  const std::string enclave = "/";
  std::string user_data = "enclave=" + enclave + ";";
  std::vector<eprosima::fastrtps::rtps::octet> ud(user_data.begin(), user_data.end());
  ud.push_back(0);
  pqos.user_data().setValue(ud);
  pqos.name(enclave.c_str());
  pqos.wire_protocol().builtin.readerHistoryMemoryPolicy =
    eprosima::fastrtps::rtps::PREALLOCATED_WITH_REALLOC_MEMORY_MODE;
  pqos.wire_protocol().builtin.writerHistoryMemoryPolicy =
    eprosima::fastrtps::rtps::PREALLOCATED_WITH_REALLOC_MEMORY_MODE;

  // rmw_fastrtps_shared_cpp `participant.cpp`: a participant listener feeding the graph cache,
  // with StatusMask::none() (discovery callbacks are not status-masked).
  GraphListener graph;
  DomainParticipant * participant = factory->create_participant(
    domain, pqos, &graph, eprosima::fastdds::dds::StatusMask::none());
  if (participant == nullptr) {
    std::fprintf(stderr, "ros_participant: could not create the participant\n");
    return 1;
  }
  Publisher * publisher = participant->create_publisher(participant->get_default_publisher_qos());
  Subscriber * subscriber =
    participant->create_subscriber(participant->get_default_subscriber_qos());

  TypeSupport info_type(new RosType<ParticipantEntitiesInfo>(
      "rmw_dds_common::msg::dds_::ParticipantEntitiesInfo_", 4096));
  TypeSupport request_type(new RosType<AddTwoIntsRequest>(
      "example_interfaces::srv::dds_::AddTwoInts_Request_", 16));
  TypeSupport response_type(new RosType<AddTwoIntsResponse>(
      "example_interfaces::srv::dds_::AddTwoInts_Response_", 8));
  info_type.register_type(participant);
  request_type.register_type(participant);
  response_type.register_type(participant);

  // ros_discovery_info (rmw_dds_common `qos_profile_rt_discovery_info`-style QoS as created by
  // rmw_fastrtps_shared_cpp `init_rmw_context_impl.cpp`).
  Topic * info_topic = participant->create_topic(
    "ros_discovery_info", info_type.get_type_name(), participant->get_default_topic_qos());
  DataWriterQos info_wqos = publisher->get_default_datawriter_qos();
  info_wqos.reliability().kind = eprosima::fastdds::dds::RELIABLE_RELIABILITY_QOS;
  info_wqos.durability().kind = eprosima::fastdds::dds::TRANSIENT_LOCAL_DURABILITY_QOS;
  info_wqos.history().kind = eprosima::fastdds::dds::KEEP_LAST_HISTORY_QOS;
  info_wqos.history().depth = 1;
  info_wqos.endpoint().history_memory_policy =
    eprosima::fastrtps::rtps::PREALLOCATED_WITH_REALLOC_MEMORY_MODE;
  info_wqos.data_sharing().off();
  // PEER_INFO_HEARTBEAT_PERIOD_S: the ros_discovery_info writer's periodic heartbeat (Fast DDS'
  // default is 3 s). A long one leaves a late-joining reader only the heartbeat the writer sends
  // when it matches that reader (StatefulWriter::matched_reader_add).
  if (const char * period = std::getenv("PEER_INFO_HEARTBEAT_PERIOD_S")) {
    info_wqos.reliable_writer_qos().times.heartbeatPeriod.seconds =
      static_cast<int32_t>(std::strtol(period, nullptr, 10));
  }
  DataWriter * info_writer = publisher->create_datawriter(info_topic, info_wqos);
  DataReaderQos info_rqos = subscriber->get_default_datareader_qos();
  info_rqos.reliability().kind = eprosima::fastdds::dds::RELIABLE_RELIABILITY_QOS;
  info_rqos.durability().kind = eprosima::fastdds::dds::TRANSIENT_LOCAL_DURABILITY_QOS;
  info_rqos.history().kind = eprosima::fastdds::dds::KEEP_ALL_HISTORY_QOS;
  info_rqos.endpoint().history_memory_policy =
    eprosima::fastrtps::rtps::PREALLOCATED_WITH_REALLOC_MEMORY_MODE;
  info_rqos.data_sharing().off();
  DataReader * info_reader = subscriber->create_datareader(info_topic, info_rqos);
  if (info_writer == nullptr || info_reader == nullptr) {
    std::fprintf(stderr, "ros_participant: could not create the ros_discovery_info endpoints\n");
    return 1;
  }

  ParticipantEntitiesInfo info;
  info.gid = to_gid(participant->guid());
  auto publish_info = [&]() {
      if (!info_writer->write(&info)) {
        std::fprintf(stderr, "ros_participant: could not write ros_discovery_info\n");
      }
    };
  publish_info();  // the context: no node yet
  NodeEntitiesInfo node;
  node.node_namespace = node_namespace;
  node.node_name = node_name;
  info.node_entities_info_seq.push_back(node);
  publish_info();  // the node, no endpoints yet

  const auto end = std::chrono::steady_clock::now() +
    std::chrono::microseconds(static_cast<int64_t>(linger * 1e6));
  // Leave as rmw does: the node goes (ros_discovery_info republished), then the endpoints and
  // the participant are deleted, which Fast DDS announces (SEDP / SPDP disposal).
  auto leave = [&](bool ok) {
      info.node_entities_info_seq.clear();
      publish_info();
      info_writer->wait_for_acknowledgments(eprosima::fastrtps::Duration_t(0, 200000000));
      participant->delete_contained_entities();
      factory->delete_participant(participant);
      return ok ? 0 : 1;
    };
  if (talking || listening) {
    return leave(
      chatter(
        participant, publisher, subscriber, info, publish_info, service, talking, count, end));
  }

  // The service: rmw_fastrtps_cpp `rmw_service.cpp` creates the request reader, then the reply
  // writer, then announces both GIDs.
  const std::string request_topic_name = "rq" + service + "Request";
  const std::string reply_topic_name = "rr" + service + "Reply";
  Topic * request_topic = participant->create_topic(
    request_topic_name, request_type.get_type_name(), participant->get_default_topic_qos());
  Topic * reply_topic = participant->create_topic(
    reply_topic_name, response_type.get_type_name(), participant->get_default_topic_qos());
  if (request_topic == nullptr || reply_topic == nullptr) {
    std::fprintf(stderr, "ros_participant: could not create the service topics\n");
    return 1;
  }
  DataReader * request_reader = nullptr;
  DataWriter * reply_writer = nullptr;
  WriterMatches reply_writer_matches;
  if (!calling) {
    request_reader =
      subscriber->create_datareader(request_topic, service_reader_qos(subscriber, REQUEST_HASH));
    reply_writer = publisher->create_datawriter(
      reply_topic, service_writer_qos(publisher, RESPONSE_HASH), &reply_writer_matches,
      eprosima::fastdds::dds::StatusMask::publication_matched());
    if (request_reader == nullptr || reply_writer == nullptr) {
      std::fprintf(stderr, "ros_participant: could not create the service\n");
      return 1;
    }
    info.node_entities_info_seq[0].reader_gid_seq.push_back(to_gid(request_reader->guid()));
    info.node_entities_info_seq[0].writer_gid_seq.push_back(to_gid(reply_writer->guid()));
    publish_info();
  }

  // The client: rmw_fastrtps_cpp `rmw_client.cpp` creates the reply reader, then the request
  // writer.
  ReaderMatches reply_reader_matches;
  WriterMatches request_writer_matches;
  DataReader * reply_reader = subscriber->create_datareader(
    reply_topic, service_reader_qos(subscriber, RESPONSE_HASH), &reply_reader_matches,
    eprosima::fastdds::dds::StatusMask::subscription_matched());
  DataWriter * request_writer = publisher->create_datawriter(
    request_topic, service_writer_qos(publisher, REQUEST_HASH), &request_writer_matches,
    eprosima::fastdds::dds::StatusMask::publication_matched());
  if (reply_reader == nullptr || request_writer == nullptr) {
    std::fprintf(stderr, "ros_participant: could not create the client\n");
    return 1;
  }
  info.node_entities_info_seq[0].reader_gid_seq.push_back(to_gid(reply_reader->guid()));
  info.node_entities_info_seq[0].writer_gid_seq.push_back(to_gid(request_writer->guid()));
  publish_info();

  std::ostringstream line;
  line << "{\"participant\": " << json_string(dotted(info.gid))
       << ", \"vendor\": \"010f\""
       << ", \"mode\": \"" << (calling ? "call" : "serve") << "\""
       << ", \"node\": {\"namespace\": " << json_string(node_namespace)
       << ", \"name\": " << json_string(node_name) << "}"
       << ", \"request_topic\": " << json_string(request_topic_name)
       << ", \"reply_topic\": " << json_string(reply_topic_name);
  if (calling) {
    line << ", \"server\": null";
  } else {
    line << ", \"server\": {\"request_reader\": "
         << json_string(dotted(to_gid(request_reader->guid())))
         << ", \"reply_writer\": " << json_string(dotted(to_gid(reply_writer->guid()))) << "}";
  }
  line << ", \"client\": {\"request_writer\": "
       << json_string(dotted(to_gid(request_writer->guid())))
       << ", \"reply_reader\": " << json_string(dotted(to_gid(reply_reader->guid()))) << "}"
       << ", \"qos\": {";
  if (!calling) {
    line << "\"request_reader\": " << qos_json(request_reader->get_qos())
         << ", \"reply_writer\": " << qos_json(reply_writer->get_qos()) << ", ";
  }
  line << "\"request_writer\": " << qos_json(request_writer->get_qos())
       << ", \"reply_reader\": " << qos_json(reply_reader->get_qos()) << "}}";
  print_line(line.str());

  bool ok = true;
  if (calling) {
    ok = call(
      graph, request_topic_name, reply_topic_name, request_writer, reply_reader,
      request_writer_matches, reply_reader_matches, count, end);
  } else {
    // Linger, answering requests, until LINGER is over or SIGTERM asks it to leave early.
    while (std::chrono::steady_clock::now() < end && !g_leave) {
      request_reader->wait_for_unread_message(eprosima::fastrtps::Duration_t(0, 50000000));
      serve(request_reader, reply_writer, reply_writer_matches);
    }
  }

  return leave(ok);
}
