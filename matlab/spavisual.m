function handle = spavisual(filename, varargin)
%SPAVISUAL  A picture of a SPACAR result: its beams and trusses at one step.
%   H = SPAVISUAL(FILE) draws the elements of FILE.sbd (written by SPACAR or
%   by flexmbd) at its last step, in a new figure, and returns the figure.
%   H = SPAVISUAL(FILE, STEP) draws step STEP. SPACAR's own SPAVISUAL (an
%   animation with modes and stresses) reads the same file; this one draws the
%   configuration only. flexmbd plots and animates results itself:
%   `flexmbd run FILE.dat --plot FILE.png` (columns against time) and
%   `--movie FILE.mp4` (the mechanism moving), or flexmbd.plot in Python.
%
%   flexmbd's (matlab/ folder of its repository); it reads the file with
%   GETFRSBF.

  if numel(filename) > 4 && strcmpi(filename(end - 3:end), '.sbd')
    filename = filename(1:end - 4);
  end
  sbd = [filename '.sbd'];
  steps = getfrsbf(sbd, 'tdef');
  step = steps;
  if nargin > 1 && isnumeric(varargin{1}) && isscalar(varargin{1})
    step = varargin{1};
  end
  x = getfrsbf(sbd, 'x', step);
  lnp = getfrsbf(sbd, 'lnp');
  ln = getfrsbf(sbd, 'ln');
  it = getfrsbf(sbd, 'it');
  % the nodes of an element that carry its ends, by SPACAR's type code
  ends = containers.Map({1, 2, 5, 7, 18}, {[1 3], [1 2], [1 3], [1 2], [1 4]});
  handle = figure('Name', sprintf('%s, step %d', filename, step));
  hold on
  planar = any(ismember(it, [5 6 7]));
  for e = 1:numel(it)
    if ~isKey(ends, it(e))
      continue                                % hinges, Euler elements: no line
    end
    nodes = ln(e, ends(it(e)));
    if any(nodes == 0)
      continue
    end
    points = zeros(2, 3);
    for k = 1:2
      numbers = lnp(nodes(k), :);
      numbers = numbers(numbers > 0);
      points(k, 1:numel(numbers)) = x(numbers);
    end
    if planar
      plot(points(:, 1), points(:, 2), 'b-o');
    else
      plot3(points(:, 1), points(:, 2), points(:, 3), 'b-o');
    end
  end
  axis equal
  grid on
  xlabel('x');
  ylabel('y');
  if ~planar
    zlabel('z');
    view(3);
  end
  title(sprintf('%s, step %d of %d', filename, step, steps), 'Interpreter', 'none');
  hold off
end
