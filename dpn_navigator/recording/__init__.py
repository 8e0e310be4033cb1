"""rosbag2 recording: the bag writer, the recorded topics, the topic recorder."""
