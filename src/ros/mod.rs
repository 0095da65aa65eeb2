//! DDS plumbing shared by the node and the command-line tools: network-safe participants, QoS, topic naming.
