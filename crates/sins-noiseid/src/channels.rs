//! The six channels every stage of the identification works on.

/// Channels: gyro x, y, z then accelerometer x, y, z.
pub const CHANNELS: usize = 6;

/// The channels' names, in that order.
pub const CHANNEL_NAMES: [&str; CHANNELS] = [
    "gyro_x", "gyro_y", "gyro_z", "accel_x", "accel_y", "accel_z",
];
