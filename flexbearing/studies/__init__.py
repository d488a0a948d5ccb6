"""Many runs at once: parameter studies (the paper's §4.4), the slip-rate validation against
published tests, and the uncertainty study over a test bearing's unknown inputs."""
