"""The flexible-rotor family (issue 38 item 3): k modal coordinates of a rotor reduced from a finite-element
model, with n balls in a race at one balancer node."""
