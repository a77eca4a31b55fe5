## Where the course's scripts look for the map, relative to their own folder: exactly one .map in
## the Gen A project's Debug folder, or in the Gen B project's CPU_FLASH folder.
function path = crs_map_file (gen)
  if gen == 'A'
    folder = '../CRSRobotProject/Debug';
  else
    folder = '../CPU_FLASH';
  end
  found = dir ([folder '/*.map']);
  if numel (found) != 1
    error ('crslab:map', 'expected one map in %s, found %d', folder, numel (found));
  end
  path = [folder '/' found(1).name];
end
