//! The `node!` macro.

/// Declares a node: a struct with its topics and data, its constructor and its [`Node`] impl
/// (with `publishers()` / `subscribers()` generated from the topics).
///
/// ```no_run
/// use horus::prelude::*;
///
/// node! {
///     /// Counts and publishes the count.
///     Counter {
///         pub {
///             count: Int64 -> "counter.value",
///         }
///         sub {
///             reset: Bool -> "counter.reset",
///         }
///         data {
///             n: i64 = 0,
///         }
///         tick(self) {
///             if let Some(r) = self.reset.try_recv() {
///                 if r.data { self.n = 0; }
///             }
///             self.n += 1;
///             self.count.send(Int64 { data: self.n });
///         }
///     }
/// }
///
/// fn main() -> Result<()> {
///     let mut sched = Scheduler::new();
///     sched.add(Counter::new()?).build()?;
///     sched.run()
/// }
/// ```
///
/// The node's name is the struct's name in snake case (`Counter` → `counter`). Optional blocks
/// after `tick`: `init(self) { … }` (returns `Result<()>`; write `Ok(())` at its end),
/// `shutdown(self) { … }` (same). Topics are `Topic<Type>` fields created with `Topic::new`;
/// `Type` is a message type name in scope (one identifier: `use` it first).
///
/// [`Node`]: crate::Node
#[macro_export]
macro_rules! node {
    (
        $(#[$meta:meta])*
        $name:ident {
            $(pub { $($pfield:ident : $pty:ident -> $ptopic:literal),* $(,)? })?
            $(sub { $($sfield:ident : $sty:ident -> $stopic:literal),* $(,)? })?
            $(data { $($dfield:ident : $dty:ty = $dinit:expr),* $(,)? })?
            tick($tself:ident) $tick:block
            $(init($iself:ident) $init:block)?
            $(shutdown($shself:ident) $shutdown:block)?
        }
    ) => {
        $(#[$meta])*
        pub struct $name {
            $($(
                /// Published topic.
                pub $pfield: $crate::Topic<$pty>,
            )*)?
            $($(
                /// Subscribed topic.
                pub $sfield: $crate::Topic<$sty>,
            )*)?
            $($(
                /// Node data.
                pub $dfield: $dty,
            )*)?
        }

        impl $name {
            /// Creates the node and its topics.
            pub fn new() -> $crate::Result<Self> {
                ::core::result::Result::Ok(Self {
                    $($( $pfield: $crate::Topic::new($ptopic)?, )*)?
                    $($( $sfield: $crate::Topic::new($stopic)?, )*)?
                    $($( $dfield: $dinit, )*)?
                })
            }
        }

        impl $crate::Node for $name {
            fn name(&self) -> &str {
                static NAME: ::std::sync::OnceLock<::std::string::String> =
                    ::std::sync::OnceLock::new();
                NAME.get_or_init(|| $crate::__private::snake_case(::core::stringify!($name)))
            }

            fn tick(&mut $tself) $tick

            $(
                fn init(&mut $iself) -> $crate::Result<()> $init
            )?

            $(
                fn shutdown(&mut $shself) -> $crate::Result<()> $shutdown
            )?

            fn publishers(&self) -> ::std::vec::Vec<$crate::TopicMetadata> {
                ::std::vec![$($(
                    $crate::TopicMetadata {
                        topic_name: ::std::string::String::from($ptopic),
                        type_name: ::std::string::String::from(
                            <$pty as $crate::Message>::TYPE_NAME,
                        ),
                    },
                )*)?]
            }

            fn subscribers(&self) -> ::std::vec::Vec<$crate::TopicMetadata> {
                ::std::vec![$($(
                    $crate::TopicMetadata {
                        topic_name: ::std::string::String::from($stopic),
                        type_name: ::std::string::String::from(
                            <$sty as $crate::Message>::TYPE_NAME,
                        ),
                    },
                )*)?]
            }
        }
    };
}

/// `MotorController` → `motor_controller`.
pub fn snake_case(name: &str) -> String {
    heck::ToSnakeCase::to_snake_case(name)
}
