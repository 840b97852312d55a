//! RIHS01 hashes against values published by ROS 2 builds.
//!
//! Sources:
//! - [J] /work/shared/docs/ros2-jazzy-wire-facts.md (read off a Jazzy build).
//! - [R] ros2/rosidl (jazzy) `rosidl_runtime_c/src/type_description/*__description.c`
//!   (generated code checked in for type_description_interfaces).
//! - [M] micro-ROS/micro_ros_arduino commit 57e9c210 (2023-03-25), generated
//!   `src/<pkg>/{msg,srv}/detail/*__struct.h` `*__TYPE_HASH` constants. That snapshot predates
//!   Jazzy; between it and jazzy the relevant .msg/.srv files changed only in comments, and its
//!   ServiceEventInfo / AddTwoInts / SetBool hashes equal [J].
//! - [P] a generated `rmw_dds_common/msg/detail/participant_entities_info__description.c`
//!   found in the public code index (Gid / NodeEntitiesInfo / ParticipantEntitiesInfo).
//! - [L] a generated `rcl_interfaces/srv/detail/list_parameters__description.c` (same index),
//!   agreeing with [M].
//! - [E] a generated `rcl_interfaces/msg/detail/parameter_event__description.c` (same index),
//!   whose expected hashes of Time, Parameter and ParameterValue agree with [J] and [M].

use horus_ros_msgs::builtin_interfaces::msg::{Duration, Time};
use horus_ros_msgs::example_interfaces::srv::AddTwoInts;
use horus_ros_msgs::rcl_interfaces::{msg as rcl_msg, srv as rcl_srv};
use horus_ros_msgs::rmw_dds_common::{Gid, NodeEntitiesInfo, ParticipantEntitiesInfo};
use horus_ros_msgs::service_msgs::msg::ServiceEventInfo;
use horus_ros_msgs::std_srvs::srv::{Empty, SetBool, Trigger};
use horus_ros_msgs::type_description_interfaces::{msg as td, srv as td_srv};
use horus_ros_msgs::{Message, Service, TypeHash};

fn hex(h: TypeHash) -> String {
    assert_eq!(h.version, 1);
    h.hex_value()
}

fn check_msg<M: Message>(expected: &str) {
    assert_eq!(hex(M::type_hash()), expected, "{}", M::TYPE_NAME);
}

fn check_srv<S: Service>(srv: &str, req: &str, resp: &str, event: Option<&str>) {
    assert_eq!(hex(S::type_hash()), srv, "{}", S::TYPE_NAME);
    check_msg::<S::Request>(req);
    check_msg::<S::Response>(resp);
    if let Some(event) = event {
        assert_eq!(hex(S::event_type_hash()), event, "{}_Event", S::TYPE_NAME);
    }
}

#[test]
fn builtin_interfaces() {
    // [J], [M]
    check_msg::<Time>("b106235e25a4c5ed35098aa0a61a3ee9c9b18d197f398b0e4206cea9acf9c197");
    // [M]
    check_msg::<Duration>("e8d009f659816f758b75334ee1a9ca5b5c0b859843261f14c7f937349599d93b");
}

#[test]
fn service_event_info() {
    // [J], [M]
    check_msg::<ServiceEventInfo>(
        "41bcbbe07a75c9b52bc96bfd5c24d7f0fc0a08c0cb7921b3373c5732345a6f45",
    );
}

#[test]
fn add_two_ints() {
    // [J], [M]
    check_srv::<AddTwoInts>(
        "e118de6bf5eeb66a2491b5bda11202e7b68f198d6f67922cf30364858239c81a",
        "000c5fd92d6b2e1a05949348f584d6d652adea1e92d691792011ac2273508302",
        "de5c030d4af33cba2749310b249737b631594703f9300495f48bffb2b44dcc2f",
        Some("32c1d140259c71e5c355115942bcb31df98b4330e4d906b1b75ccb1c9b3ce6c8"),
    );
}

#[test]
fn std_srvs() {
    // [J] (service, request, response), [M] (all, event)
    check_srv::<SetBool>(
        "abe9e4bb6b41b40e6789712c00ec8871923e089af3f667a79992a428cff2da0a",
        "c62fbb99d94e1b25e8ef9e109f9581956bb1b3361a45a4e5810c36a90d29932e",
        "d0814e7f7b4880ab77e9c57426c7aa1562ab69f11eef8e2e968812f9cbd0b059",
        Some("3c4c20015afb4303eafd347b1d6a786f171a89c814726961a9593ef10df878cf"),
    );
    // [M]
    check_srv::<Empty>(
        "5888399dedec5ccc85ea6451949fd2c9f97bfdf963f9a588821639fcd31b5d19",
        "458eaf200a3f63d9cc53d19436edebc0c140ef4c93ca75d5bd4ce19fd7759e35",
        "0a2858b3f60df644a61d0fa44cfc923a3d3628e0ad9c8ad8534b1a2c92a413dc",
        Some("66fa7fcfb5f2bf04b9a8a55603318c5c402edfc4bd56bb0ed7b602990c29305a"),
    );
    check_srv::<Trigger>(
        "eeff2cd6fa5ad9d27cdf4dec64818317839b62f212a91e6b5304b634b2062c5f",
        "d010825374ce8918e72bfd826c82603e60f45419e932ea976f807b74a863a199",
        "2d946c21e2fc3f1e9ca6986a8191d85fcc70097a8bb7771a053564bc47009cdf",
        Some("ec4a1d26b0575e61906890342aba9523a2360e9845857c5590fa6e23bc39e1c2"),
    );
}

#[test]
fn rcl_interfaces_messages() {
    // [M]
    check_msg::<rcl_msg::FloatingPointRange>(
        "e6af23a23c177fee5f3075c8b1e435162a9b63c863d78c06017460b49684262d",
    );
    check_msg::<rcl_msg::IntegerRange>(
        "f7b7fdc0f65f07702e099218e13288c3963bcb9345bde78b560e6cd19800fc5a",
    );
    check_msg::<rcl_msg::ListParametersResult>(
        "237ae3428413dcbcfb452b510c42355f3a2b021dc091afa3e18526d57022f1cd",
    );
    check_msg::<rcl_msg::Parameter>(
        "ddfe6442cffc462317adb5c92536a7b6dd55858c5c3e1e328165a6b73c2831af",
    );
    check_msg::<rcl_msg::ParameterDescriptor>(
        "52175dbfda6c51153101d33d2a9da05743f66f02d5ab2ca9ec4709b46b73d704",
    );
    check_msg::<rcl_msg::ParameterType>(
        "df29ed057a834862187be24dd187d981790ff3ea6502f4cd27b432cbc42c6d46",
    );
    check_msg::<rcl_msg::ParameterValue>(
        "115fc089a387e23c7ecd3525c9189c379109119d6ab82e8dfbde0fdf6a7f9b68",
    );
    check_msg::<rcl_msg::SetParametersResult>(
        "cfcc0fb0371ee5159b403960ef4300f8f9d2f1fd6117c8666b7f9654d528a9b1",
    );
    // [E]
    check_msg::<rcl_msg::ParameterEvent>(
        "043e627780fcad87a22d225bc2a037361dba713fca6a6b9f4b869a5aa0393204",
    );
}

#[test]
fn rcl_interfaces_services() {
    // [M]; ListParameters also [L]
    check_srv::<rcl_srv::ListParameters>(
        "3e6062bfbb27bfb8730d4cef2558221f51a11646d78e7bb30a1e83afac3aad9d",
        "a1b0b5d6b967a5b8ac5bc8563c3ea678f349e312a6a4967227c5a96bc5ce38df",
        "31b937b82de3612426be79f231e386259f97e8dc843e3f2845288b4bfa296bdd",
        Some("89c5b5aaf68ec925ae9bbc5569ee21de82959b4d1496dbd498792ad825b9b292"),
    );
    check_srv::<rcl_srv::GetParameters>(
        "bf9803d5c74cf989a5de3e0c2e99444599a627c7ff75f97b8c05b01003675cbc",
        "135a9e1c3d7cebef792f6687d7ddf99949b21a0bd9a320d863a9110a3f5cf4d6",
        "9fa773b46e39cc5d02db6224d8fd520bb9caeeffc2b27c96c1e59431baba9f2a",
        Some("84eeb9247b09067c35bd8750d5c8555b700e394a616737c4624f15ae02e64c4d"),
    );
    check_srv::<rcl_srv::GetParameterTypes>(
        "da199c878688b3e530bdfe3ca8f74cb9fa0c303101e980a9e8f260e25e1c80ca",
        "87d7ec5ef545d4daa289d500025d31fb2437bc8b8365ca367161c4dac4be33fd",
        "ac1335dce67c478e669434f6ac2fbff34fcd529580f272d3006785ba8b54e47f",
        Some("9516adca0cc885d46a59c2362fb8eb5f4906b046518266f8c645b454b0dddc60"),
    );
    check_srv::<rcl_srv::SetParameters>(
        "56eed9a67e169f9cb6c1f987bc88f868c14a8fc9f743a263bc734c154015d7e0",
        "130d46386b7e84ea9ecf60608a4d83cbe5e5cb7c6cc5b712b7a4e3a6c254e932",
        "7a0e8140a0b8d98308fa81a5403a766e610af29a239caf54b7553227906fc266",
        Some("5060f52369bcff7f9dbd6eca21ee521859e471e71b33a8a8df26d5236fe54a80"),
    );
    check_srv::<rcl_srv::SetParametersAtomically>(
        "0e192ef259c07fc3c07a13191d27002222e65e00ccec653ca05e856f79285fcd",
        "db0bd950ed5ed867a0e90b225e44dea382d762c0762ff3e0ee842190042a59e5",
        "31b1a38c5b0b9d893ee24da45f69638f4561c78461d82d52750f429b534502b8",
        Some("42fc0821e6e8fcff2b150cefc7d8269f0ce65139e1dc715b15267a4bcf63a189"),
    );
    check_srv::<rcl_srv::DescribeParameters>(
        "845b484d71eb0673dae682f2e3ba3c4851a65a3dcfb97bddd82c5b57e91e4cff",
        "05dd1c2bc87dec2627105c8070d6f9725c781a4f2ab852975bf105462b82b644",
        "ad6747319613c6131589e062e095b469a46cc764f7d0f12a001a49e6cd893995",
        Some("3deba64c035093033c690184834441551a53128ea2539f71f2596fbc4ed9de43"),
    );
}

#[test]
fn type_description_interfaces() {
    // [R], [M]
    check_msg::<td::Field>("c0b01379cd4226281285ccaf6be46653968f855f7c5e41614ff5d7a854efef7c");
    check_msg::<td::FieldType>("a70b6dd919645a03a3586f7f821defbc886ea3e531a1d95cc0f380a3973ccaa6");
    check_msg::<td::IndividualTypeDescription>(
        "55c827d86c3c141bdd318fe6c22e11190e4d3b37c8f4f9751a084aa05ce96560",
    );
    check_msg::<td::KeyValue>("274fe56bf14f33c7512e34c646a37579ee36779f745f049a9760763e817f0c42");
    check_msg::<td::TypeDescription>(
        "739f2508c9fa3a6f330913ff5b9d25fb74159a077da71e1087f51a60c12a080b",
    );
    check_msg::<td::TypeSource>("faeaec7596c04ecf5b6e99ad225e4c7cbb997ad5435f793526fb3984d011aae5");
    // [M]
    check_srv::<td_srv::GetTypeDescription>(
        "69b9c19c1021405984cc60dbbb1edceb147a6538b411d812ba6afabeed962cd5",
        "470f56ccbcf13d55c78c8b735fb12da03e639e5acded994426c89d94778d9e28",
        "648c49d976240861a482f961c5621ddd0d2135d8cce6f297a76d4f6376d93b75",
        Some("491e3350e7a0b11918fb16a523cf01a22d76fdaa53c43b52164fea14aabb5612"),
    );
}

#[test]
fn rmw_dds_common() {
    // [P]
    check_msg::<Gid>("ab6f21cfbb0a6dbb837161e1110c2051a2850ed9f9c53944d7115d9bcebedf71");
    check_msg::<NodeEntitiesInfo>(
        "8ffef65ee2d088c63b1e8fcd31e800ba9fc8dbe0ee15ca60d1676de5218087a7",
    );
    check_msg::<ParticipantEntitiesInfo>(
        "91a0593bacdcc50ea9bdcf849a938b128412cc1ea821245c663bcd26f83c295e",
    );
}

#[test]
fn hash_is_cached_and_stable() {
    let a = Time::type_hash();
    let b = Time::type_hash();
    assert_eq!(a, b);
    assert_eq!(a, horus_ros_msgs::rihs::rihs01(&Time::type_description()));
}

// The standard message types a robot program needs first. No Jazzy-generated `*.json` type
// description of them is in the public code index; each value below is instead one that ROS 2
// graphs and tools publish and that independent projects record: [T] `ros2 topic info -v`
// output captured from a Jazzy graph (Twist), rosbag2 `metadata.yaml` `type_description_hash`
// entries (String, Log), and golden tables of independent RIHS01 implementations (rmw_zenoh
// key expressions, rosbags-style typestores, micro-ROS-style hash tables) that agree with one
// another. Each value was found in at least two unrelated sources; the ones marked (1) in one
// only — they share the code path (one primitive field `data`) with the others.

#[test]
fn std_msgs() {
    use horus_ros_msgs::std_msgs::msg as m;
    check_msg::<m::String>("df668c740482bbd48fb39d76a70dfd4bd59db1288021743503259e948f6b1a18");
    check_msg::<m::Header>("f49fb3ae2cf070f793645ff749683ac6b06203e41c891e17701b1cb597ce6a01");
    check_msg::<m::Empty>("20b625256f32d5dbc0d04fee44f43c41e51c70d3502f84b4a08e7a9c26a96312");
    check_msg::<m::Bool>("feb91e995ff9ebd09c0cb3d2aed18b11077585839fb5db80193b62d74528f6c9");
    check_msg::<m::Byte>("41e1a3345f73fe93ede006da826a6ee274af23dd4653976ff249b0f44e3e798f");
    check_msg::<m::Char>("3ad2d04dd29ba19d04b16659afa3ccaedd691914b02a64e82e252f2fa6a586a9");
    check_msg::<m::Int8>("26525065a403d972cb672f0777e333f0c799ad444ae5fcd79e43d1e73bd0f440");
    check_msg::<m::Int32>("b6578ded3c58c626cfe8d1a6fb6e04f706f97e9f03d2727c9ff4e74b1cef0deb");
    check_msg::<m::UInt64>("fbdc52018fc13755dce18024d1a671c856aa8b4aaf63adfb095b608f98e8c943");
    check_msg::<m::Float64>("705ba9c3d1a09df43737eb67095534de36fd426c0587779bda2bc51fe790182a");
    // (1)
    check_msg::<m::Int16>("1dcc3464e47c288a55f943a389d337cdb06804de3f5cd7a266b0de718eee17e5");
    check_msg::<m::Int64>("8cd1048c2f186b6bd9a92472dc1ce51723c0833a221e2b7aecfff111774f4b49");
    check_msg::<m::UInt8>("6138bd83d8c3569cb80a667db03cfc1629f529fee79d944c39c34e352e72f010");
    check_msg::<m::UInt16>("08a406e4b022bc22e907f985d6a9e9dd1d4fbecae573549cf49350113e7757b1");
    check_msg::<m::UInt32>("a5c874829b752bc5fa190024b0ad76f578cc278271e855c7d02a818b3516fb4a");
    check_msg::<m::Float32>("7170d3d8f841f7be3172ce5f4f59f3a4d7f63b0447e8b33327601ad64d83d6e2");
}

#[test]
fn geometry_msgs() {
    use horus_ros_msgs::geometry_msgs::msg as g;
    check_msg::<g::Vector3>("cc12fe83e4c02719f1ce8070bfd14aecd40f75a96696a67a2a1f37f7dbb0765d");
    check_msg::<g::Point>("6963084842a9b04494d6b2941d11444708d892da2f4b09843b9c43f42a7f6881");
    // Its .msg gives default values (w = 1): not hashed.
    check_msg::<g::Quaternion>("8a765f66778c8ff7c8ab94afcc590a2ed5325a1d9a076ffff38fbce36f458684");
    check_msg::<g::Pose>("d501954e9476cea2996984e812054b68026ae0bfae789d9a10b23daf35cc90fa");
    check_msg::<g::PoseStamped>("10f3786d7d40fd2b54367835614bff85d4ad3b5dab62bf8bca0cc232d73b4cd8");
    // [T]
    check_msg::<g::Twist>("9c45bf16fe0983d80e3cfe750d6835843d265a9a6c46bd2e609fcddde6fb8d2a");
    check_msg::<g::TwistStamped>(
        "5f0fcd4f81d5d06ad9b4c4c63e3ea51b82d6ae4d0558f1d475229b1121db6f64",
    );
    assert_eq!(g::Quaternion::default().w, 1.0, "the .msg default");
}

#[test]
fn sensor_msgs() {
    use horus_ros_msgs::sensor_msgs::msg as s;
    check_msg::<s::LaserScan>("64c191398013af96509d518dac71d5164f9382553fce5c1f8cca5be7924bd828");
    check_msg::<s::Imu>("7d9a00ff131080897a5ec7e26e315954b8eae3353c3f995c55faf71574000b5b");
    check_msg::<s::JointState>("a13ee3a330e346c9d87b5aa18d24e11690752bd33a0350f11c5882bc9179260e");
}

#[test]
fn rosout_log() {
    check_msg::<rcl_msg::Log>("e28ce254ca8abc06abf92773b74602cdbf116ed34fbaf294fb9f81da9f318eac");
    assert_eq!(
        (rcl_msg::Log::DEBUG, rcl_msg::Log::INFO, rcl_msg::Log::FATAL),
        (10, 20, 50)
    );
}
