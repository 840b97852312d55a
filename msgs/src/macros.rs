//! Crate-internal macros that declare a ROS message struct together with its [`Message`] impl.
//!
//! [`Message`]: crate::Message

/// Declares `pub struct $name { pub fields… }` (serde, field order = `.msg` order) and implements
/// [`crate::Message`] for it, describing each field from its Rust type through
/// [`crate::RosField`]. A field may add `= "default"` (the `.msg` default, kept in descriptions
/// but not hashed) and `=> |t| t.bounded_string(256)` to adjust its [`FieldType`] (bounds).
///
/// [`FieldType`]: crate::type_description_interfaces::msg::FieldType
macro_rules! ros_message {
    (
        $(#[$meta:meta])*
        $name:ident = $ros_name:literal {
            $(
                $(#[$fmeta:meta])*
                $field:ident : $ty:ty $(= $default:literal)? $(=> $modify:expr)?
            ),* $(,)?
        }
    ) => {
        $(#[$meta])*
        #[derive(Clone, Debug, PartialEq, Default, serde::Serialize, serde::Deserialize)]
        pub struct $name {
            $(
                $(#[$fmeta])*
                pub $field: $ty,
            )*
        }

        impl $crate::Message for $name {
            const TYPE_NAME: &'static str = $ros_name;

            fn type_description() -> $crate::TypeDescription {
                #[allow(unused_mut)]
                let mut b = $crate::DescriptionBuilder::new($ros_name);
                $(
                    b = b.field_with::<$ty>(
                        stringify!($field),
                        ros_message!(@modify $($modify)?),
                    );
                    $( b = b.default_value($default); )?
                )*
                b.build()
            }
        }
    };
    (@modify) => { |t| t };
    (@modify $modify:expr) => { $modify };
}

/// Declares a unit struct for a ROS service and implements [`crate::Service`] for it.
macro_rules! ros_service {
    (
        $(#[$meta:meta])*
        $name:ident = $ros_name:literal, $req:ty, $resp:ty
    ) => {
        $(#[$meta])*
        #[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
        pub struct $name;

        impl $crate::Service for $name {
            type Request = $req;
            type Response = $resp;
            const TYPE_NAME: &'static str = $ros_name;
        }
    };
}
